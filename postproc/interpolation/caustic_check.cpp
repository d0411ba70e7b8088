#include "postproc/interpolation/caustic_check.h"

#include <cmath>
#include <string>

#include "postproc/interpolation/flag_regions.h"
#include "postproc/interpolation/luminance_planes.h"
#include "postproc/interpolation/window_sums.h"

namespace pathfarm {

std::vector<uint8_t> movingCausticPixels(const FrameImage& frame, const CausticCheckSettings& settings) {
  const int width = frame.width(), height = frame.height();
  if (!frame.hasChannel("moving_caustic.Y")) return std::vector<uint8_t>(frame.pixelCount(), 0);
  const std::string whose = "caustic check: the frame";
  const std::vector<float>& caustic = frame.channel("moving_caustic.Y");
  std::vector<double> focused(frame.pixelCount()), seen(frame.pixelCount());
  for (size_t p = 0; p < focused.size(); ++p) {
    focused[p] = caustic[p];
    seen[p] = caustic[p] > 0.0f ? 1.0 : 0.0;
  }
  const std::vector<double> lightSums = boxSums(luminancePlane(frame, "", whose), width, height, settings.radius);
  const std::vector<double> focusedSums = boxSums(focused, width, height, settings.radius);
  const std::vector<double> seenSums = boxSums(seen, width, height, settings.radius);
  const bool hasVariance = frame.hasChannel("variance.R") && frame.hasChannel("variance.G") && frame.hasChannel("variance.B");
  const std::vector<double> varianceSums =
      hasVariance ? boxSums(luminanceVarianceBound(frame, "variance.", whose), width, height, settings.radius)
                  : std::vector<double>(frame.pixelCount(), 0.0);
  const std::vector<uint8_t> spots = pixelsWhere(width, height, [&](int x, int y) {
    const size_t p = static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x);
    return focusedSums[p] > 0 && seenSums[p] >= settings.minPixels &&
           focusedSums[p] > settings.share * lightSums[p] + settings.z * std::sqrt(varianceSums[p]);
  });
  return dilated(spots, width, height, settings.margin);
}

}  // namespace pathfarm
