#include "postproc/metrics/relmse.h"

#include <algorithm>
#include <cmath>
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

constexpr int kErrorBlock = 8;

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

// Over pixels and channels, ((image - reference)^2 - variance) / (d^2 + 0.01), without the
// squared difference when `image` is null.
MeanEstimate estimatedAgainstNoisyReference(const FrameImage* image, const FrameImage& reference) {
  if (image && (image->width() != reference.width() || image->height() != reference.height()))
    throw std::invalid_argument("relMSE needs two frames of the same resolution");
  const int w = reference.width(), h = reference.height();
  struct Channel {
    const std::vector<float>& ref;
    const std::vector<float>& variance;
    const std::vector<float>* values;
  };
  std::vector<Channel> channels;
  for (const char* channel : {"R", "G", "B"}) {
    const std::string varianceName = std::string("variance.") + channel;
    if (!reference.hasChannel(varianceName))
      throw std::invalid_argument("no \"" + varianceName + "\" channel to estimate the noise from");
    channels.push_back({reference.channel(channel), reference.channel(varianceName),
                        image ? &image->channel(channel) : nullptr});
  }
  MeanEstimate estimate;
  for (int by = 0; by < h; by += kErrorBlock)
    for (int bx = 0; bx < w; bx += kErrorBlock) {
      double blockSum = 0, blockCount = 0;
      for (const Channel& c : channels)
        for (int y = by; y < std::min(h, by + kErrorBlock); ++y)
          for (int x = bx; x < std::min(w, bx + kErrorBlock); ++x) {
            const size_t p = static_cast<size_t>(y) * w + x;
            const double d = neighbourMean(c.ref, w, h, x, y);
            const double difference = c.values ? double{(*c.values)[p]} - c.ref[p] : 0.0;
            const double noise = c.variance[p];
            blockSum += (c.values ? difference * difference - noise : noise) / (d * d + 0.01);
            blockCount += 1;
          }
      estimate.addBlock(blockSum, blockCount);
    }
  return estimate;
}

}  // namespace

double MeanEstimate::standardError() const {
  if (blocks < 2) return 0;
  // The variance of sum / count from the blocks' deviations s_b - n_b m.
  const double m = mean();
  const double deviations = blockSquares - 2 * m * blockCross + m * m * blockCountSquares;
  return std::sqrt(std::max(0.0, deviations) * blocks / (blocks - 1)) / count;
}

void MeanEstimate::addBlock(double blockSum, double blockCount) {
  sum += blockSum;
  count += blockCount;
  blockSquares += blockSum * blockSum;
  blockCross += blockSum * blockCount;
  blockCountSquares += blockCount * blockCount;
  blocks += 1;
}

MeanEstimate& MeanEstimate::operator+=(const MeanEstimate& other) {
  sum += other.sum;
  count += other.count;
  blockSquares += other.blockSquares;
  blockCross += other.blockCross;
  blockCountSquares += other.blockCountSquares;
  blocks += other.blocks;
  return *this;
}

MeanEstimate relMseLessReferenceNoise(const FrameImage& image, const FrameImage& reference) {
  return estimatedAgainstNoisyReference(&image, reference);
}

MeanEstimate ownRelMseFromVariance(const FrameImage& reference) {
  return estimatedAgainstNoisyReference(nullptr, reference);
}

}  // namespace pathfarm
