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
  tbb::parallel_for(size_t{0}, partial.size(), [&](size_t c) { partial[c] = body(c * kChunk, std::min(n, (c + 1) * kChunk)); });
  std::array<double, K> total{};
  for (const auto& p : partial)
    for (size_t k = 0; k < K; ++k) total[k] += p[k];
  return total;
}

double dot(const std::vector<float>& a, const std::vector<float>& b) {
  return reduce<1>(a.size(), [&](size_t begin, size_t end) {
    double sum = 0;
    for (size_t i = begin; i < end; ++i) sum += static_cast<double>(a[i]) * b[i];
    return std::array<double, 1>{sum};
  })[0];
}

template <class Body>
void forEach(size_t n, Body body) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) body(i);
  });
}

// Jacobi-preconditioned conjugate gradients on A^T W A x = A^T W b, from x as given, with
// the vector updates of an iteration fused into two passes. Returns the relative residual.
double conjugateGradients(const PoissonSystem& system, std::vector<float>& x, int maxIterations, float tolerance,
                          int& iterations) {
  const size_t n = system.size();
  const std::vector<float> b = system.rightHandSide();
  std::vector<float> inverseDiagonal = system.diagonal();
  for (float& d : inverseDiagonal) d = d > 0 ? 1 / d : 0;
  const double bNorm = std::sqrt(dot(b, b));
  std::vector<float> r(n), p(n), q(n);
  system.applyNormal(x, q);
  const auto [rz0, rr0] = reduce<2>(n, [&](size_t begin, size_t end) {
    std::array<double, 2> sums{};
    for (size_t i = begin; i < end; ++i) {
      r[i] = b[i] - q[i];
      p[i] = r[i] * inverseDiagonal[i];
      sums[0] += static_cast<double>(r[i]) * p[i];
      sums[1] += static_cast<double>(r[i]) * r[i];
    }
    return sums;
  });
  double rz = rz0, rNorm = std::sqrt(rr0);
  if (bNorm == 0) return rNorm == 0 ? 0 : 1;  // no data at all: nothing to fit
  for (int k = 0; k < maxIterations && rNorm > tolerance * bNorm; ++k) {
    system.applyNormal(p, q);
    const double pq = dot(p, q);
    if (!(pq > 0)) break;
    const auto a = static_cast<float>(rz / pq);
    // x += a p, r -= a q, and the next r.z and r.r; z = D^-1 r is recomputed below.
    const auto [rzNext, rr] = reduce<2>(n, [&](size_t begin, size_t end) {
      std::array<double, 2> sums{};
      for (size_t i = begin; i < end; ++i) {
        x[i] += a * p[i];
        r[i] -= a * q[i];
        sums[0] += static_cast<double>(r[i]) * r[i] * inverseDiagonal[i];
        sums[1] += static_cast<double>(r[i]) * r[i];
      }
      return sums;
    });
    const auto beta = static_cast<float>(rzNext / rz);
    rz = rzNext;
    forEach(n, [&](size_t i) { p[i] = r[i] * inverseDiagonal[i] + beta * p[i]; });
    rNorm = std::sqrt(rr);
    ++iterations;
  }
  return rNorm / bNorm;
}

// IRLS weights for the L1 norm: a row's squared error, weighted by 1 / |scaled residual|,
// equals its absolute error at the current solution.
void reweightForL1(PoissonSystem& system, const std::vector<float>& x, float alpha, float epsilon) {
  auto factors = system.residuals(x);
  for (size_t k = 0; k < PoissonSystem::kBlocks; ++k) {
    const float scale = k == PoissonSystem::Data ? alpha : 1.0f;
    forEach(factors[k].size(), [&](size_t i) { factors[k][i] = 1.0f / std::max(scale * std::abs(factors[k][i]), epsilon); });
  }
  system.setWeightFactors(factors);
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
  for (size_t c = 0; c < 3; ++c) {
    PoissonSystem system(frames, c, settings.alpha);
    std::vector<float> x = system.primal();
    // Non-finite samples must not poison the whole window: start from 0 there.
    for (float& v : x)
      if (!std::isfinite(v)) v = 0;
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
    total.relativeResidual = std::max(total.relativeResidual, residual);
    const size_t pixels = frames[0]->pixelCount();
    for (size_t f = 0; f < frames.size(); ++f)
      result[f][c].assign(x.begin() + static_cast<std::ptrdiff_t>(f * pixels),
                          x.begin() + static_cast<std::ptrdiff_t>((f + 1) * pixels));
  }
  if (stats) *stats = total;
  return result;
}

}  // namespace pathfarm
