#pragma once
// A sum of samples and of their squares per color channel: a pixel's mean and the
// variance of that mean, which the frame renderers write next to the beauty.
#include <algorithm>
#include <array>
#include <cstdint>

#include "renderer/math/vecmath.h"

namespace pathfarm {

struct SampleMoments {
  std::array<double, 3> sum{}, squares{};

  void add(const Rgb& v) {
    for (int c = 0; c < 3; ++c) {
      sum[static_cast<size_t>(c)] += v[c];
      squares[static_cast<size_t>(c)] += static_cast<double>(v[c]) * v[c];
    }
  }
  double mean(size_t c, uint32_t n) const { return n > 0 ? sum[c] / n : 0.0; }
  // The variance of the mean of n samples: their unbiased variance over n.
  double varianceOfMean(size_t c, uint32_t n) const {
    if (n < 2) return 0;
    const double m = sum[c] / n;
    return std::max(0.0, squares[c] - n * m * m) / (static_cast<double>(n - 1) * n);
  }
};

}  // namespace pathfarm
