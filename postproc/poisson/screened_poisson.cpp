#include "postproc/poisson/screened_poisson.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "postproc/poisson/poisson_system.h"

namespace pathfarm {
namespace {

constexpr size_t kChunk = 16384;

// Runs body(begin, end) over fixed chunks of [0, n) in parallel and returns the chunks'
// results summed in chunk order: the same bits for any thread count.
template <size_t K, class Body>
std::array<double, K> reduce(size_t n, Body body) {
  std::vector<std::array<double, K>> partial((n + kChunk - 1) / kChunk);
  tbb::parallel_for(size_t{0}, partial.size(),
                    [&](size_t c) { partial[c] = body(c * kChunk, std::min(n, (c + 1) * kChunk)); });
  std::array<double, K> total{};
  for (const auto& p : partial)
    for (size_t k = 0; k < K; ++k) total[k] += p[k];
  return total;
}

using Channels = std::array<double, 3>;

// Per color channel, the sum over the interleaved vectors of a[i] * b[i] * c[i].
Channels dot3(const std::vector<float>& a, const std::vector<float>& b) {
  const auto sums = reduce<3>(a.size() / 3, [&](size_t begin, size_t end) {
    std::array<double, 3> partial{};
    for (size_t g = begin; g < end; ++g)
      for (size_t c = 0; c < 3; ++c) partial[c] += static_cast<double>(a[3 * g + c]) * b[3 * g + c];
    return partial;
  });
  return sums;
}

template <class Body>
void forEach(size_t n, Body body) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) body(i);
  });
}

// Jacobi-preconditioned conjugate gradients on A^T W A x = A^T W b, from x as given, one
// independent solve per color channel run side by side (scalars per channel), with the
// vector updates of an iteration fused into two passes. Stops when every channel's
// residual is below the tolerance; returns the largest relative residual.
double conjugateGradients(const PoissonSystem& system, std::vector<float>& x, int maxIterations, float tolerance,
                          int& iterations) {
  const size_t n = system.size(), rows = n / 3;
  const std::vector<float> b = system.rightHandSide();
  std::vector<float> inverseDiagonal = system.diagonal();
  for (float& d : inverseDiagonal) d = d > 0 ? 1 / d : 0;
  const Channels bb = dot3(b, b);
  std::vector<float> r(n), p(n), q(n);
  system.applyNormal(x, q);
  const auto start = reduce<6>(rows, [&](size_t begin, size_t end) {
    std::array<double, 6> sums{};
    for (size_t i = 3 * begin; i < 3 * end; ++i) {
      r[i] = b[i] - q[i];
      p[i] = r[i] * inverseDiagonal[i];
      sums[i % 3] += static_cast<double>(r[i]) * p[i];
      sums[3 + i % 3] += static_cast<double>(r[i]) * r[i];
    }
    return sums;
  });
  Channels rz{start[0], start[1], start[2]}, rr{start[3], start[4], start[5]};
  const auto relative = [&] {
    double worst = 0;
    for (size_t c = 0; c < 3; ++c) worst = std::max(worst, bb[c] > 0 ? std::sqrt(rr[c] / bb[c]) : (rr[c] > 0 ? 1 : 0));
    return worst;
  };
  for (int k = 0; k < maxIterations && relative() > tolerance; ++k) {
    system.applyNormal(p, q);
    const Channels pq = dot3(p, q);
    std::array<float, 3> a{};
    for (size_t c = 0; c < 3; ++c) a[c] = pq[c] > 0 && rz[c] > 0 ? static_cast<float>(rz[c] / pq[c]) : 0.0f;
    // x += a p, r -= a q, and the next r.z and r.r; z = D^-1 r is recomputed below.
    const auto sums = reduce<6>(rows, [&](size_t begin, size_t end) {
      std::array<double, 6> partial{};
      for (size_t i = 3 * begin; i < 3 * end; ++i) {
        x[i] += a[i % 3] * p[i];
        r[i] -= a[i % 3] * q[i];
        partial[i % 3] += static_cast<double>(r[i]) * r[i] * inverseDiagonal[i];
        partial[3 + i % 3] += static_cast<double>(r[i]) * r[i];
      }
      return partial;
    });
    std::array<float, 3> beta{};
    for (size_t c = 0; c < 3; ++c) {
      beta[c] = rz[c] > 0 ? static_cast<float>(sums[c] / rz[c]) : 0.0f;
      rz[c] = sums[c];
      rr[c] = sums[3 + c];
    }
    forEach(n, [&](size_t i) { p[i] = r[i] * inverseDiagonal[i] + beta[i % 3] * p[i]; });
    ++iterations;
  }
  return relative();
}

// IRLS weights for the L1 norm: a row's squared error, weighted by 1 / |scaled residual|,
// equals its absolute error at the current solution.
void reweightForL1(PoissonSystem& system, const std::vector<float>& x, float alpha, float epsilon) {
  auto factors = system.residuals(x);
  for (size_t k = 0; k < PoissonSystem::kBlocks; ++k) {
    const float scale = k == PoissonSystem::Data ? alpha : 1.0f;
    forEach(factors[k].size(),
            [&](size_t i) { factors[k][i] = 1.0f / std::max(scale * std::abs(factors[k][i]), epsilon); });
  }
  system.setWeightFactors(std::move(factors));
}

}  // namespace

PoissonNorm parsePoissonNorm(const std::string& text) {
  if (text == "l1") return PoissonNorm::L1;
  if (text == "l2") return PoissonNorm::L2;
  throw std::invalid_argument("unknown norm \"" + text + "\" (expected l1 or l2)");
}

std::vector<GradientFrame::Color> reconstructWindow(const std::vector<const GradientFrame*>& frames,
                                                    const PoissonSettings& settings, PoissonStats* stats) {
  if (frames.empty()) throw std::invalid_argument("a Poisson window needs at least one frame");
  if (!(settings.alpha > 0)) throw std::invalid_argument("alpha must be positive");
  std::vector<GradientFrame::Color> result(frames.size());
  PoissonStats total;
  PoissonSystem system(frames, settings.alpha);
  std::vector<float> x = system.primal();
  double residual = 0;
  if (settings.norm == PoissonNorm::L2) {
    residual = conjugateGradients(system, x, settings.maxIterations, settings.tolerance, total.iterations);
  } else {
    residual = conjugateGradients(system, x, settings.irlsIterations, settings.tolerance, total.iterations);
    for (int round = 1; round < settings.irlsRounds; ++round) {
      reweightForL1(system, x, settings.alpha, settings.irlsEpsilon);
      residual = conjugateGradients(system, x, settings.irlsIterations, settings.tolerance, total.iterations);
    }
  }
  total.relativeResidual = residual;
  const size_t pixels = frames[0]->pixelCount();
  for (size_t f = 0; f < frames.size(); ++f)
    for (size_t c = 0; c < 3; ++c) {
      auto& plane = result[f][c];
      plane.resize(pixels);
      for (size_t p = 0; p < pixels; ++p) plane[p] = x[3 * (f * pixels + p) + c];
    }
  if (stats) *stats = total;
  return result;
}

}  // namespace pathfarm
