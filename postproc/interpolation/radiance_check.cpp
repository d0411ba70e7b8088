#include "postproc/interpolation/radiance_check.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "postproc/filters/decomposed_frame.h"
#include "postproc/interpolation/solid_regions.h"
#include "postproc/interpolation/window_sums.h"

namespace pathfarm {
namespace {

constexpr const char* kRgb[3] = {"R", "G", "B"};
constexpr float kLuminance[3] = {0.2126f, 0.7152f, 0.0722f};

const std::vector<float>& channelOf(const FrameImage& frame, const std::string& name, const char* which) {
  if (!frame.hasChannel(name))
    throw std::invalid_argument(std::string("radiance check: the ") + which + " frame has no channel \"" + name + "\"");
  return frame.channel(name);
}

// The luminance of `<prefix>R/G/B`, or with `deviation` the bound sum_k w_k sigma_k of its
// standard deviation from per-channel variances.
std::vector<double> luminance(const FrameImage& frame, const std::string& prefix, const char* which,
                              bool deviation = false) {
  std::vector<double> out(frame.pixelCount(), 0.0);
  for (int c = 0; c < 3; ++c) {
    const std::vector<float>& values = channelOf(frame, prefix + kRgb[c], which);
    for (size_t p = 0; p < out.size(); ++p)
      out[p] += kLuminance[c] * (deviation ? std::sqrt(std::max(0.0f, values[p])) : values[p]);
  }
  if (deviation)
    for (double& v : out) v *= v;
  return out;
}

}  // namespace

std::vector<uint8_t> radianceMismatch(const FrameImage& interpolated, const FrameImage& features,
                                      const RadianceCheckSettings& settings) {
  if (interpolated.width() != features.width() || interpolated.height() != features.height())
    throw std::invalid_argument("radiance check: the interpolated frame and the features differ in size");
  const int width = features.width(), height = features.height();
  std::vector<uint8_t> mismatch(features.pixelCount(), 0);
  const WindowSums beauty(luminance(features, "", "features'"), width, height);
  for (const std::string& c : decompositionComponents(interpolated)) {
    std::vector<double> difference = luminance(interpolated, c + ".color.", "interpolated");
    const std::vector<double> rendered = luminance(features, c + ".color.", "features'");
    for (size_t p = 0; p < difference.size(); ++p) difference[p] -= rendered[p];
    const WindowSums differences(difference, width, height);
    const WindowSums variances(luminance(features, c + ".variance.", "features'", true), width, height);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const double d = std::abs(differences.around(x, y, settings.radius));
        if (d > settings.z * std::sqrt(variances.around(x, y, settings.radius)) &&
            d > settings.relative * beauty.around(x, y, settings.radius))
          mismatch[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)] = 1;
      }
  }
  return solidRegions(mismatch, width, height, settings.solidRadius);
}

}  // namespace pathfarm
