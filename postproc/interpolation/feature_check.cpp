#include "postproc/interpolation/feature_check.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "postproc/filters/decomposed_frame.h"

namespace pathfarm {
namespace {

const std::vector<float>& channelOf(const FrameImage& frame, const std::string& name, const char* which) {
  if (!frame.hasChannel(name))
    throw std::invalid_argument(std::string("feature check: the ") + which + " frame has no channel \"" + name + "\"");
  return frame.channel(name);
}

// The luminance of `<prefix>R/G/B` at every pixel.
std::vector<float> luminance(const FrameImage& frame, const std::string& prefix, const char* which) {
  const std::vector<float>&r = channelOf(frame, prefix + "R", which), &g = channelOf(frame, prefix + "G", which),
  &b = channelOf(frame, prefix + "B", which);
  std::vector<float> out(r.size());
  for (size_t p = 0; p < out.size(); ++p) out[p] = 0.2126f * r[p] + 0.7152f * g[p] + 0.0722f * b[p];
  return out;
}

}  // namespace

std::vector<uint8_t> featureMismatch(const FrameImage& interpolated, const FrameImage& features,
                                     const FeatureCheckSettings& settings) {
  if (interpolated.width() != features.width() || interpolated.height() != features.height())
    throw std::invalid_argument("feature check: the interpolated frame and the features differ in size");
  const size_t pixels = interpolated.pixelCount();
  std::vector<uint8_t> mismatch(pixels, 0);
  const std::vector<float> beautyInterpolated = luminance(interpolated, "", "interpolated");
  const std::vector<float> beautyFeatures = luminance(features, "", "features'");
  const auto significant = [&](float value, float beauty) {
    return value > std::max(settings.significance * beauty, 1e-6f);
  };
  for (const std::string& c : decompositionComponents(interpolated)) {
    const std::vector<float>& depth = channelOf(interpolated, c + ".depth.Z", "interpolated");
    const std::vector<float>& trueDepth = channelOf(features, c + ".depth.Z", "features'");
    const std::vector<float>&nx = channelOf(features, c + ".normal.X", "features'"),
    &ny = channelOf(features, c + ".normal.Y", "features'"), &nz = channelOf(features, c + ".normal.Z", "features'");
    const std::vector<float> colorInterpolated = luminance(interpolated, c + ".color.", "interpolated");
    const std::vector<float> colorFeatures = luminance(features, c + ".color.", "features'");
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
