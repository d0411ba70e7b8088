#include "postproc/interpolation/forward_splat.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace pathfarm {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

float depthOf(const SplatSource& source, size_t p) {
  if (source.depth == nullptr) return 0.0f;
  const float d = (*source.depth)[p];
  return d > 0.0f ? d : kInf;
}

// Calls f(target, weight) for the bilinear footprint of the source at pixel (px, py)
// moved by (dx, dy). The targets and weights follow from the displacement's whole and
// fractional parts, not from the position it lands at, so that they are the same bits
// wherever the source is: in a frame, or in a band of its rows (the interpolation's
// windows of rows), and at 4K's large coordinates as at small ones.
template <typename F>
void footprint(int px, int py, float dx, float dy, int width, int height, F&& f) {
  const float fx = std::floor(dx), fy = std::floor(dy);
  if (!(std::abs(fx) <= static_cast<float>(width) && std::abs(fy) <= static_cast<float>(height))) return;
  const int x0 = px + static_cast<int>(fx), y0 = py + static_cast<int>(fy);
  const float ax = dx - fx, ay = dy - fy;
  const float wx[2] = {1.0f - ax, ax}, wy[2] = {1.0f - ay, ay};
  for (int j = 0; j < 2; ++j) {
    const int ty = y0 + j;
    if (ty < 0 || ty >= height || wy[j] <= 0.0f) continue;
    for (int i = 0; i < 2; ++i) {
      const int tx = x0 + i;
      if (tx < 0 || tx >= width || wx[i] <= 0.0f) continue;
      f(static_cast<size_t>(ty) * static_cast<size_t>(width) + static_cast<size_t>(tx), wx[i] * wy[j]);
    }
  }
}

}  // namespace

SplatResult forwardSplat(const SplatSource& source, const SplatSettings& settings) {
  if (source.values == nullptr) throw std::invalid_argument("forward splat: no values");
  const Planes& values = *source.values;
  const int width = values.width, height = values.height;
  const size_t pixels = values.pixelCount();
  if (source.dx.size() != pixels || source.dy.size() != pixels || (!source.active.empty() && source.active.size() != pixels) ||
      (source.depth != nullptr && source.depth->size() != pixels))
    throw std::invalid_argument("forward splat: planes do not match the " + std::to_string(width) + "x" +
                                std::to_string(height) + " values");
  const size_t channels = values.channels.size();

  // Calls f(target, weight) for where source p lands, if it splats.
  auto landing = [&](size_t p, auto&& f) {
    if (!source.active.empty() && source.active[p] == 0) return;
    if (!std::isfinite(source.dx[p]) || !std::isfinite(source.dy[p])) return;
    const int px = static_cast<int>(p % static_cast<size_t>(width)), py = static_cast<int>(p / static_cast<size_t>(width));
    footprint(px, py, source.dx[p], source.dy[p], width, height, f);
  };

  // Pass 1: the reference (nearest strong) depth of every target.
  std::vector<float> nearest(pixels, kInf);
  std::vector<uint8_t> strong(pixels, 0);
  for (size_t p = 0; p < pixels; ++p) {
    const float d = depthOf(source, p);
    landing(p, [&](size_t t, float w) {
      if (w >= settings.strongFootprint) {
        if (!strong[t] || d < nearest[t]) nearest[t] = d;
        strong[t] = 1;
      }
    });
  }
  // Targets with no strong contribution keep every contribution. Pass 2: accumulate the kept contributions.
  SplatResult result;
  result.values = Planes(width, height, static_cast<int>(channels));
  result.weight.assign(pixels, 0.0f);
  std::vector<double> depthSum(pixels, 0.0);
  std::vector<double> sums(pixels * channels, 0.0);
  std::vector<double> weights(pixels, 0.0), finiteWeights(pixels, 0.0);
  for (size_t p = 0; p < pixels; ++p) {
    const float d = depthOf(source, p);
    landing(p, [&](size_t t, float w) {
      if (strong[t] && !(d <= nearest[t] * (1.0f + settings.depthTolerance) + 1e-6f)) return;
      weights[t] += w;
      if (std::isfinite(d)) {
        depthSum[t] += static_cast<double>(w) * d;
        finiteWeights[t] += w;
      }
      for (size_t c = 0; c < channels; ++c) sums[t * channels + c] += static_cast<double>(w) * values.channels[c][p];
    });
  }
  result.depth.assign(pixels, kInf);
  result.covered.assign(pixels, 0);
  for (size_t t = 0; t < pixels; ++t) {
    result.weight[t] = static_cast<float>(weights[t]);
    if (weights[t] < settings.minCoverage) continue;
    result.covered[t] = 1;
    // A pixel whose kept surfaces are all "nothing there" keeps depth +inf.
    result.depth[t] = finiteWeights[t] > 0.0 ? static_cast<float>(depthSum[t] / finiteWeights[t]) : kInf;
    for (size_t c = 0; c < channels; ++c)
      result.values.channels[c][t] = static_cast<float>(sums[t * channels + c] / weights[t]);
  }
  return result;
}

size_t fillHolesFromBackground(SplatResult& result) {
  const int width = result.values.width, height = result.values.height;
  std::vector<size_t> holes;
  for (size_t t = 0; t < result.covered.size(); ++t)
    if (!result.covered[t]) holes.push_back(t);
  size_t filled = 0;
  const size_t channels = result.values.channels.size();
  while (!holes.empty()) {
    std::vector<std::pair<size_t, size_t>> fills;  // (hole, source)
    std::vector<size_t> remaining;
    for (size_t t : holes) {
      const int x = static_cast<int>(t % static_cast<size_t>(width)), y = static_cast<int>(t / static_cast<size_t>(width));
      size_t best = t;
      float bestDepth = -1.0f;
      const int nx[4] = {x - 1, x + 1, x, x}, ny[4] = {y, y, y - 1, y + 1};
      for (int k = 0; k < 4; ++k) {
        if (nx[k] < 0 || nx[k] >= width || ny[k] < 0 || ny[k] >= height) continue;
        const size_t n = static_cast<size_t>(ny[k]) * static_cast<size_t>(width) + static_cast<size_t>(nx[k]);
        if (!result.covered[n]) continue;
        const float d = std::isnan(result.depth[n]) ? 0.0f : result.depth[n];
        if (d > bestDepth) {
          bestDepth = d;
          best = n;
        }
      }
      if (best == t)
        remaining.push_back(t);
      else
        fills.emplace_back(t, best);
    }
    if (fills.empty()) break;
    for (const auto& [t, n] : fills) {
      for (size_t c = 0; c < channels; ++c) result.values.channels[c][t] = result.values.channels[c][n];
      result.depth[t] = result.depth[n];
    }
    for (const auto& [t, n] : fills) result.covered[t] = 1;
    filled += fills.size();
    holes.swap(remaining);
  }
  return filled;
}

}  // namespace pathfarm
