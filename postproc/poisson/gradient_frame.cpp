#include "postproc/poisson/gradient_frame.h"

#include <cmath>
#include <stdexcept>

namespace pathfarm {
namespace {

const std::vector<float>& required(const FrameImage& image, const std::string& name, const std::string& label) {
  if (!image.hasChannel(name))
    throw std::invalid_argument(label + ": missing channel \"" + name +
                                "\" (render with --integrator gpt or tgpt, docs/gradient-domain.md)");
  return image.channel(name);
}

GradientFrame::Color colorLayer(const FrameImage& image, const std::string& layer, const std::string& label) {
  GradientFrame::Color color;
  for (size_t c = 0; c < 3; ++c) color[c] = required(image, layer + "." + kColorChannels[c], label);
  return color;
}

// The layer's variance summed over the channels, or nothing when a channel lacks one.
std::vector<float> summedVariance(const FrameImage& image, const std::string& layer) {
  std::vector<float> sum;
  for (const char* channel : kColorChannels)
    if (!image.hasChannel(layer + ".variance." + channel)) return {};
  sum.assign(static_cast<size_t>(image.width()) * static_cast<size_t>(image.height()), 0.0f);
  for (const char* channel : kColorChannels) {
    const auto& variance = image.channel(layer + ".variance." + channel);
    for (size_t p = 0; p < sum.size(); ++p) sum[p] += variance[p];
  }
  return sum;
}

}  // namespace

GradientFrame GradientFrame::fromImage(const FrameImage& image, const std::string& label) {
  GradientFrame frame;
  frame.width = image.width();
  frame.height = image.height();
  frame.primal = colorLayer(image, "primal", label);
  frame.gradientX = colorLayer(image, "gradient_x", label);
  frame.gradientY = colorLayer(image, "gradient_y", label);
  frame.directEmission = colorLayer(image, "direct_emission", label);
  for (size_t k = 0; k < kLayers; ++k) frame.variance[k] = summedVariance(image, kLayerNames[k]);
  if (!image.hasChannel("temporal.valid.Y")) return frame;

  frame.temporal = colorLayer(image, "temporal", label);
  frame.mixedX = colorLayer(image, "mixed_x", label);
  frame.mixedY = colorLayer(image, "mixed_y", label);
  const auto& valid = image.channel("temporal.valid.Y");
  const auto& tx = required(image, "temporal.target.X", label);
  const auto& ty = required(image, "temporal.target.Y", label);
  frame.temporalTarget.assign(frame.pixelCount(), -1);
  std::vector<char> claimed(frame.pixelCount(), 0);
  for (size_t p = 0; p < frame.pixelCount(); ++p) {
    const bool finite = std::isfinite(frame.temporal[0][p]) && std::isfinite(frame.temporal[1][p]) &&
                        std::isfinite(frame.temporal[2][p]);
    if (valid[p] != 1.0f || !finite || !(tx[p] >= 0) || !(ty[p] >= 0) || tx[p] >= static_cast<float>(frame.width) ||
        ty[p] >= static_cast<float>(frame.height))
      continue;
    const size_t target = static_cast<size_t>(ty[p]) * static_cast<size_t>(frame.width) + static_cast<size_t>(tx[p]);
    if (claimed[target]) continue;
    claimed[target] = 1;
    frame.temporalTarget[p] = static_cast<int32_t>(target);
  }
  return frame;
}

}  // namespace pathfarm
