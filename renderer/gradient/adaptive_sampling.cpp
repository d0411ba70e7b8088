#include "renderer/gradient/adaptive_sampling.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace pathfarm {
namespace {

constexpr std::array<float, 5> kSmoothing{0.1f, 0.2f, 0.4f, 0.2f, 0.1f};
constexpr float kClampToMean = 8.0f;

int clampIndex(int i, int n) { return std::min(std::max(i, 0), n - 1); }

}  // namespace

std::vector<float> samplingDensity(const std::vector<float>& relativeVariance, int width, int height) {
  const auto at = [&](const std::vector<float>& image, int x, int y) {
    return image[static_cast<size_t>(clampIndex(y, height)) * static_cast<size_t>(width) +
                 static_cast<size_t>(clampIndex(x, width))];
  };
  std::vector<float> clean(relativeVariance.size());
  for (size_t i = 0; i < clean.size(); ++i)
    clean[i] = std::isfinite(relativeVariance[i]) ? std::max(relativeVariance[i], 0.0f) : 0.0f;
  std::vector<float> median(clean.size()), rows(clean.size()), smooth(clean.size());
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      std::array<float, 25> window;
      for (int i = 0; i < 25; ++i) window[static_cast<size_t>(i)] = at(clean, x + i % 5 - 2, y + i / 5 - 2);
      std::nth_element(window.begin(), window.begin() + 12, window.end());
      median[static_cast<size_t>(y * width + x)] = window[12];
    }
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      float sum = 0;
      for (int i = 0; i < 5; ++i) sum += kSmoothing[static_cast<size_t>(i)] * at(median, x + i - 2, y);
      rows[static_cast<size_t>(y * width + x)] = sum;
    }
  double mean = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      float sum = 0;
      for (int i = 0; i < 5; ++i) sum += kSmoothing[static_cast<size_t>(i)] * at(rows, x, y + i - 2);
      smooth[static_cast<size_t>(y * width + x)] = sum;
      mean += sum;
    }
  mean /= static_cast<double>(std::max<size_t>(smooth.size(), 1));
  for (float& v : smooth) v = std::min(v, static_cast<float>(kClampToMean * mean));
  return smooth;
}

std::vector<uint32_t> allocateSamples(const std::vector<float>& density, uint64_t budget) {
  double total = 0;
  for (float d : density) total += d;
  std::vector<uint32_t> samples(density.size());
  double carry = 0;
  for (size_t i = 0; i < density.size(); ++i) {
    const double share = total > 0 ? density[i] / total : 1.0 / static_cast<double>(density.size());
    const double wanted = static_cast<double>(budget) * share + carry;
    samples[i] = static_cast<uint32_t>(std::max(0.0, std::floor(wanted)));
    carry = wanted - samples[i];
  }
  return samples;
}

}  // namespace pathfarm
