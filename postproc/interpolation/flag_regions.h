#pragma once
// Per-pixel flag masks (one byte per pixel, row-major, 1 = flagged) as the checks that judge
// a pixel by the window around it make and shape them (caustic_check.h, radiance_check.h,
// solid_regions.h): the pixels whose window passes a test, and the regions grown from them.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace pathfarm {

// 1 at the pixels (x, y) where `passes(x, y)` holds.
template <class Test>
std::vector<uint8_t> pixelsWhere(int width, int height, Test passes) {
  std::vector<uint8_t> flags(static_cast<size_t>(width) * static_cast<size_t>(height), 0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      if (passes(x, y)) flags[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)] = 1;
  return flags;
}

// The pixels with a flagged pixel in the square of side 2 radius + 1 around them (a
// morphological dilation).
std::vector<uint8_t> dilated(const std::vector<uint8_t>& mask, int width, int height, int radius);

// `strong` and the pixels of `weak` it reaches through `weak` pixels in at most `reach`
// steps (8-connected).
std::vector<uint8_t> grownRegions(std::vector<uint8_t> strong, const std::vector<uint8_t>& weak, int width,
                                  int height, int reach);

}  // namespace pathfarm
