#include "postproc/interpolation/caustic_check.h"

#include <string>

#include "image/luminance.h"
#include "postproc/interpolation/flag_regions.h"
#include "postproc/interpolation/window_sums.h"

namespace pathfarm {

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
