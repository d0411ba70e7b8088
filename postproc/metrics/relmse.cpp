#include "postproc/metrics/relmse.h"

#include <stdexcept>

namespace pathfarm {

double relMse(const std::vector<float>& image, const std::vector<float>& reference) {
  if (image.size() != reference.size() || image.empty())
    throw std::invalid_argument("relMSE needs two non-empty buffers of the same size");
  double sum = 0;
  for (size_t i = 0; i < image.size(); ++i) sum += relativeSquaredError(image[i], reference[i]);
  return sum / static_cast<double>(image.size());
}

double relMse(const FrameImage& image, const FrameImage& reference,
              const std::vector<std::string>& channels) {
  if (image.width() != reference.width() || image.height() != reference.height())
    throw std::invalid_argument("relMSE needs two frames of the same resolution");
  double sum = 0;
  for (const std::string& name : channels) sum += relMse(image.channel(name), reference.channel(name));
  return sum / static_cast<double>(channels.size());
}

double expectedRelMse(const FrameImage& image) {
  double sum = 0;
  for (const char* channel : {"R", "G", "B"}) {
    const std::string name = std::string("variance.") + channel;
    if (!image.hasChannel(name)) throw std::invalid_argument("no \"" + name + "\" channel to estimate the noise from");
    const std::vector<float>& value = image.channel(channel);
    const std::vector<float>& variance = image.channel(name);
    for (size_t p = 0; p < value.size(); ++p) sum += variance[p] / (double{value[p]} * value[p] + 0.01);
  }
  return image.pixelCount() > 0 ? sum / (3.0 * static_cast<double>(image.pixelCount())) : 0;
}

}  // namespace pathfarm
