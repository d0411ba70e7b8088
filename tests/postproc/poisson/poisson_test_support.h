#pragma once
// Gradient frames built from known clean images, for the Poisson tests.
#include <cmath>
#include <functional>
#include <vector>

#include "postproc/poisson/gradient_frame.h"
#include "test_support.h"

namespace pathfarm::poisson_test {

using Image = std::function<float(int c, int x, int y)>;

// A frame whose primal, spatial differences and (with `next` and `shift`) temporal
// differences towards `next` shifted by `shift` pixels are exact for `clean`.
inline GradientFrame exactFrame(int w, int h, const Image& clean, const Image* next = nullptr, int shift = 0) {
  GradientFrame f;
  f.width = w;
  f.height = h;
  const size_t n = f.pixelCount();
  for (int c = 0; c < 3; ++c) {
    auto& primal = f.primal[static_cast<size_t>(c)];
    auto& gx = f.gradientX[static_cast<size_t>(c)];
    auto& gy = f.gradientY[static_cast<size_t>(c)];
    primal.assign(n, 0.0f);
    gx.assign(n, 0.0f);
    gy.assign(n, 0.0f);
    f.directEmission[static_cast<size_t>(c)].assign(n, 0.0f);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t p = static_cast<size_t>(y * w + x);
        primal[p] = clean(c, x, y);
        if (x + 1 < w) gx[p] = clean(c, x + 1, y) - clean(c, x, y);
        if (y + 1 < h) gy[p] = clean(c, x, y + 1) - clean(c, x, y);
      }
  }
  if (!next) return f;
  f.temporalTarget.assign(n, -1);
  for (auto* layer : {&f.temporal, &f.mixedX, &f.mixedY})
    for (auto& plane : *layer) plane.assign(n, 0.0f);
  // I_next(target(p)) - I(p) where p = (x, y) has a target.
  const auto temporal = [&](int c, int x, int y) { return (*next)(c, x + shift, y) - clean(c, x, y); };
  const auto inside = [&](int x) { return x + shift >= 0 && x + shift < w; };  // else no correspondence
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!inside(x)) continue;
      const size_t p = static_cast<size_t>(y * w + x);
      f.temporalTarget[p] = y * w + x + shift;
      for (int c = 0; c < 3; ++c) {
        const auto i = static_cast<size_t>(c);
        f.temporal[i][p] = temporal(c, x, y);
        if (x + 1 < w && inside(x + 1)) f.mixedX[i][p] = temporal(c, x + 1, y) - temporal(c, x, y);
        if (y + 1 < h) f.mixedY[i][p] = temporal(c, x, y + 1) - temporal(c, x, y);
      }
    }
  return f;
}

// Adds noise of amplitude `amplitude` to one layer, made exactly zero-mean per channel.
inline void addZeroMeanNoise(GradientFrame::Color& layer, float amplitude, uint32_t seed) {
  for (int c = 0; c < 3; ++c) {
    auto& plane = layer[static_cast<size_t>(c)];
    std::vector<double> noise(plane.size());
    double mean = 0;
    for (size_t p = 0; p < plane.size(); ++p) {
      noise[p] = amplitude * (2.0 * test_support::hashed(seed, c, static_cast<int>(p), 7) - 1.0);
      mean += noise[p] / static_cast<double>(plane.size());
    }
    for (size_t p = 0; p < plane.size(); ++p) plane[p] += static_cast<float>(noise[p] - mean);
  }
}

// max |a - b| / max |b| over every channel and pixel.
inline double relativeError(const GradientFrame::Color& a, const Image& clean, int w, int h) {
  double error = 0, scale = 0;
  for (int c = 0; c < 3; ++c)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const double ref = clean(c, x, y);
        error = std::max(error, std::abs(a[static_cast<size_t>(c)][static_cast<size_t>(y * w + x)] - ref));
        scale = std::max(scale, std::abs(ref));
      }
  return error / scale;
}

}  // namespace pathfarm::poisson_test
