#pragma once
// The flagged regions of a per-pixel mask that contain a solid square: a morphological
// opening (erosion, then dilation, by a square of side 2 radius + 1). A pixel stays
// flagged when some square of that side holding it is flagged throughout; pixels outside
// the frame count as flagged, so a region is not lost for touching an edge. Checks that
// judge a pixel by a window (radiance_check.h) flag whole windows' worth of pixels around
// a real difference, and such a region is left exactly as it was; a statistic that only
// grazes its threshold flags thin and scattered pixels, which vanish.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "postproc/interpolation/flag_regions.h"
#include "postproc/interpolation/window_sums.h"

namespace pathfarm {

inline std::vector<uint8_t> solidRegions(const std::vector<uint8_t>& mask, int width, int height, int radius) {
  if (radius <= 0) return mask;
  // Window sums count the flagged pixels of each square inside the frame; the square is
  // flagged throughout when the count equals its area inside the frame.
  const auto inside = [&](int x, int y) {
    const int x0 = std::max(0, x - radius), x1 = std::min(width, x + radius + 1);
    const int y0 = std::max(0, y - radius), y1 = std::min(height, y + radius + 1);
    return static_cast<double>((x1 - x0) * (y1 - y0));
  };
  const WindowSums flagged(std::vector<double>(mask.begin(), mask.end()), width, height);
  const std::vector<uint8_t> centres =
      pixelsWhere(width, height, [&](int x, int y) { return flagged.around(x, y, radius) == inside(x, y); });
  return dilated(centres, width, height, radius);
}

}  // namespace pathfarm
