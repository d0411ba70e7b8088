#include "postproc/metrics/relmse.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "postproc/metrics/error_terms.h"

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

// Over pixels and channels, ((image - reference)^2 - variance) / (d^2 + 0.01), without the
// squared difference when `image` is null (error_terms.h).
MeanEstimate estimatedAgainstNoisyReference(const FrameImage* image, const FrameImage& reference) {
  const BlockedTerms terms = errorTerms(image, reference);
  MeanEstimate estimate;
  for (size_t b = 0; b < terms.sums.size(); ++b) estimate.addBlock(terms.sums[b], terms.counts[b]);
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
