#include "postproc/interpolation/feature_check.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "image/luminance.h"
#include "postproc/filters/decomposed_frame.h"

namespace pathfarm {
namespace {

constexpr const char* kInterpolated = "feature check: the interpolated frame";
constexpr const char* kFeatures = "feature check: the features' frame";

// The luminance of `<prefix>R/G/B` at every pixel; `whose` names the frame (channelOf).
std::vector<float> luminancePlane(const FrameImage& frame, const std::string& prefix, const std::string& whose) {
  const std::vector<float>&r = channelOf(frame, prefix + "R", whose), &g = channelOf(frame, prefix + "G", whose),
  &b = channelOf(frame, prefix + "B", whose);
  std::vector<float> out(r.size());
  for (size_t p = 0; p < out.size(); ++p) out[p] = luminance(r[p], g[p], b[p]);
  return out;
}

}  // namespace

std::vector<uint8_t> featureMismatch(const FrameImage& interpolated, const FrameImage& features,
                                     const FeatureCheckSettings& settings) {
  if (interpolated.width() != features.width() || interpolated.height() != features.height())
    throw std::invalid_argument("feature check: the interpolated frame and the features differ in size");
  const size_t pixels = interpolated.pixelCount();
  std::vector<uint8_t> mismatch(pixels, 0);
  const std::vector<float> beautyInterpolated = luminancePlane(interpolated, "", kInterpolated);
  const std::vector<float> beautyFeatures = luminancePlane(features, "", kFeatures);
  const auto significant = [&](float value, float beauty) {
    return value > std::max(settings.significance * beauty, 1e-6f);
  };
  for (const std::string& c : decompositionComponents(interpolated)) {
    const std::vector<float>& depth = channelOf(interpolated, c + ".depth.Z", kInterpolated);
    const std::vector<float>& trueDepth = channelOf(features, c + ".depth.Z", kFeatures);
    const std::vector<float>&nx = channelOf(features, c + ".normal.X", kFeatures),
    &ny = channelOf(features, c + ".normal.Y", kFeatures), &nz = channelOf(features, c + ".normal.Z", kFeatures);
    const std::vector<float> colorInterpolated = luminancePlane(interpolated, c + ".color.", kInterpolated);
    const std::vector<float> colorFeatures = luminancePlane(features, c + ".color.", kFeatures);
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
