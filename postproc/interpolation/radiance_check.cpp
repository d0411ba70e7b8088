#include "postproc/interpolation/radiance_check.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

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

// `strong` and the pixels of `weak` it reaches through `weak` pixels in at most `reach`
// steps (8-connected).
std::vector<uint8_t> grownRegions(std::vector<uint8_t> strong, const std::vector<uint8_t>& weak, int width,
                                  int height, int reach) {
  std::vector<size_t> front;
  for (size_t p = 0; p < strong.size(); ++p)
    if (strong[p]) front.push_back(p);
  for (int step = 0; step < reach && !front.empty(); ++step) {
    std::vector<size_t> next;
    for (const size_t p : front) {
      const int x = static_cast<int>(p % static_cast<size_t>(width)), y = static_cast<int>(p / static_cast<size_t>(width));
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
          const size_t q = static_cast<size_t>(ny) * static_cast<size_t>(width) + static_cast<size_t>(nx);
          if (weak[q] && !strong[q]) {
            strong[q] = 1;
            next.push_back(q);
          }
        }
    }
    front = std::move(next);
  }
  return strong;
}

}  // namespace

std::vector<uint8_t> radianceMismatch(const FrameImage& interpolated, const FrameImage& features,
                                      const RadianceCheckSettings& settings) {
  if (interpolated.width() != features.width() || interpolated.height() != features.height())
    throw std::invalid_argument("radiance check: the interpolated frame and the features differ in size");
  const int width = features.width(), height = features.height();
  std::vector<uint8_t> mismatch(features.pixelCount(), 0), weak(features.pixelCount(), 0);
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
        const double deviation = std::sqrt(variances.around(x, y, settings.radius));
        const double light = beauty.around(x, y, settings.radius);
        const size_t p = static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x);
        if (d > settings.z * deviation && d > settings.relative * light) mismatch[p] = 1;
        if (d > settings.growZ * deviation && d > settings.growRelative * light) weak[p] = 1;
      }
  }
  return grownRegions(solidRegions(mismatch, width, height, settings.solidRadius), weak, width, height,
                      settings.growReach);
}

}  // namespace pathfarm
