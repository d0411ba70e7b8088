#include "postproc/interpolation/feature_check.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "postproc/filters/decomposed_frame.h"
#include "postproc/interpolation/luminance_planes.h"

namespace pathfarm {
namespace {

constexpr const char* kInterpolated = "feature check: the interpolated frame";
constexpr const char* kFeatures = "feature check: the features' frame";

}  // namespace

std::vector<uint8_t> featureMismatch(const FrameImage& interpolated, const FrameImage& features,
                                     const FeatureCheckSettings& settings) {
  if (interpolated.width() != features.width() || interpolated.height() != features.height())
    throw std::invalid_argument("feature check: the interpolated frame and the features differ in size");
  const size_t pixels = interpolated.pixelCount();
  std::vector<uint8_t> mismatch(pixels, 0);
  const std::vector<double> beautyInterpolated = luminancePlane(interpolated, "", kInterpolated);
  const std::vector<double> beautyFeatures = luminancePlane(features, "", kFeatures);
  const auto significant = [&](double value, double beauty) {
    return value > std::max(static_cast<double>(settings.significance) * beauty, 1e-6);
  };
  for (const std::string& c : decompositionComponents(interpolated)) {
    const std::vector<float>& depth = channelOf(interpolated, c + ".depth.Z", kInterpolated);
    const std::vector<float>& trueDepth = channelOf(features, c + ".depth.Z", kFeatures);
    const std::vector<float>&nx = channelOf(features, c + ".normal.X", kFeatures),
    &ny = channelOf(features, c + ".normal.Y", kFeatures), &nz = channelOf(features, c + ".normal.Z", kFeatures);
    const std::vector<double> colorInterpolated = luminancePlane(interpolated, c + ".color.", kInterpolated);
    const std::vector<double> colorFeatures = luminancePlane(features, c + ".color.", kFeatures);
    for (size_t p = 0; p < pixels; ++p) {
      const bool there = depth[p] > 0.0f;
      const bool really = nx[p] != 0.0f || ny[p] != 0.0f || nz[p] != 0.0f;
      if (there && really) {
        if (std::abs(depth[p] - trueDepth[p]) > settings.depthTolerance * trueDepth[p]) mismatch[p] = 1;
      } else if (there) {
        if (significant(colorInterpolated[p], beautyInterpolated[p])) mismatch[p] = 1;
      } else if (really) {
        if (significant(colorFeatures[p], beautyFeatures[p])) mismatch[p] = 1;
      }
    }
  }
  return mismatch;
}

}  // namespace pathfarm
