#include "postproc/interpolation/caustic_check.h"

#include <algorithm>
#include <string>

#include "image/luminance.h"
#include "postproc/interpolation/flag_regions.h"

namespace pathfarm {
namespace {

// Sums over the (2 radius + 1)^2 window around every pixel (cut at the frame's edges):
// columns first, then rows, each added in the same order wherever the frame starts. So a
// band of a frame's rows, given `radius` rows around it, has its sums in the same bits as
// the whole frame (the upsampler's windows of rows), which a summed-area table would not.
std::vector<double> boxSums(const std::vector<double>& values, int width, int height, int radius) {
  std::vector<double> columns(values.size(), 0.0), sums(values.size(), 0.0);
  const auto at = [width](int x, int y) { return static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x); };
  for (int y = 0; y < height; ++y)
    for (int v = std::max(0, y - radius); v <= std::min(height - 1, y + radius); ++v)
      for (int x = 0; x < width; ++x) columns[at(x, y)] += values[at(x, v)];
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int u = std::max(0, x - radius); u <= std::min(width - 1, x + radius); ++u) sums[at(x, y)] += columns[at(u, y)];
  return sums;
}

}  // namespace

std::vector<uint8_t> movingCausticPixels(const FrameImage& frame, const CausticCheckSettings& settings) {
  const int width = frame.width(), height = frame.height();
  if (!frame.hasChannel("moving_caustic.Y")) return std::vector<uint8_t>(frame.pixelCount(), 0);
  const std::string whose = "caustic check: the frame";
  const std::vector<float>& r = channelOf(frame, "R", whose);
  const std::vector<float>& g = channelOf(frame, "G", whose);
  const std::vector<float>& b = channelOf(frame, "B", whose);
  const std::vector<float>& caustic = frame.channel("moving_caustic.Y");
  std::vector<double> light(frame.pixelCount()), focused(frame.pixelCount()), seen(frame.pixelCount());
  for (size_t p = 0; p < light.size(); ++p) {
    light[p] = luminance<double>(r[p], g[p], b[p]);
    focused[p] = caustic[p];
    seen[p] = caustic[p] > 0.0f ? 1.0 : 0.0;
  }
  const std::vector<double> lightSums = boxSums(light, width, height, settings.radius);
  const std::vector<double> focusedSums = boxSums(focused, width, height, settings.radius);
  const std::vector<double> seenSums = boxSums(seen, width, height, settings.radius);
  const std::vector<uint8_t> spots = pixelsWhere(width, height, [&](int x, int y) {
    const size_t p = static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x);
    return focusedSums[p] > 0 && focusedSums[p] > settings.share * lightSums[p] && seenSums[p] >= settings.minPixels;
  });
  return dilated(spots, width, height, settings.margin);
}

}  // namespace pathfarm
