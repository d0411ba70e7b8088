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

}  // namespace pathfarm
