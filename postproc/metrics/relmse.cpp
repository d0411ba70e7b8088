#include "postproc/metrics/relmse.h"

#include <algorithm>
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

namespace {

// The mean of the 8 neighbours of pixel (x, y) inside the frame.
double neighbourMean(const std::vector<float>& values, int width, int height, int x, int y) {
  double sum = 0;
  int count = 0;
  for (int ny = std::max(0, y - 1); ny <= std::min(height - 1, y + 1); ++ny)
    for (int nx = std::max(0, x - 1); nx <= std::min(width - 1, x + 1); ++nx) {
      if (nx == x && ny == y) continue;
      sum += values[static_cast<size_t>(ny) * width + nx];
      ++count;
    }
  return count > 0 ? sum / count : values[static_cast<size_t>(y) * width + x];
}

// The mean over pixels and channels of ((image - reference)^2 - variance) / (d^2 + 0.01),
// without the squared difference when `image` is null.
double estimatedAgainstNoisyReference(const FrameImage* image, const FrameImage& reference) {
  if (image && (image->width() != reference.width() || image->height() != reference.height()))
    throw std::invalid_argument("relMSE needs two frames of the same resolution");
  const int w = reference.width(), h = reference.height();
  double sum = 0;
  for (const char* channel : {"R", "G", "B"}) {
    const std::string varianceName = std::string("variance.") + channel;
    if (!reference.hasChannel(varianceName))
      throw std::invalid_argument("no \"" + varianceName + "\" channel to estimate the noise from");
    const std::vector<float>& ref = reference.channel(channel);
    const std::vector<float>& variance = reference.channel(varianceName);
    const std::vector<float>* values = image ? &image->channel(channel) : nullptr;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t p = static_cast<size_t>(y) * w + x;
        const double d = neighbourMean(ref, w, h, x, y);
        const double squared = values ? (double{(*values)[p]} - ref[p]) * (double{(*values)[p]} - ref[p]) : 0.0;
        sum += (values ? squared - variance[p] : double{variance[p]}) / (d * d + 0.01);
      }
  }
  return reference.pixelCount() > 0 ? sum / (3.0 * static_cast<double>(reference.pixelCount())) : 0;
}

}  // namespace

double relMseLessReferenceNoise(const FrameImage& image, const FrameImage& reference) {
  return estimatedAgainstNoisyReference(&image, reference);
}

double ownRelMseFromVariance(const FrameImage& reference) { return estimatedAgainstNoisyReference(nullptr, reference); }

}  // namespace pathfarm
