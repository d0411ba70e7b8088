#include "postproc/poisson/screened_poisson.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "postproc/poisson/poisson_system.h"

namespace pathfarm {
namespace {

// A dot product summed in fixed chunks and then in chunk order: the same bits for any
// thread count.
double dot(const std::vector<float>& a, const std::vector<float>& b) {
  constexpr size_t kChunk = 16384;
  std::vector<double> partial((a.size() + kChunk - 1) / kChunk, 0.0);
  tbb::parallel_for(size_t{0}, partial.size(), [&](size_t c) {
    double sum = 0;
    const size_t end = std::min(a.size(), (c + 1) * kChunk);
    for (size_t i = c * kChunk; i < end; ++i) sum += static_cast<double>(a[i]) * b[i];
    partial[c] = sum;
  });
  double total = 0;
  for (double p : partial) total += p;
  return total;
}

template <class Body>
void forEach(size_t n, Body body) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) body(i);
  });
}

// Jacobi-preconditioned conjugate gradients on A^T W A x = A^T W b, from x as given.
// Returns the relative residual reached.
double conjugateGradients(const PoissonSystem& system, std::vector<float>& x, int maxIterations, float tolerance,
                          int& iterations) {
  const size_t n = system.size();
  const std::vector<float> b = system.rightHandSide();
  const std::vector<float> diagonal = system.diagonal();
  const double bNorm = std::sqrt(dot(b, b));
  std::vector<float> r(n), z(n), p(n), q(n);
  system.applyNormal(x, q);
  forEach(n, [&](size_t i) { r[i] = b[i] - q[i]; });
  const auto precondition = [&] { forEach(n, [&](size_t i) { z[i] = diagonal[i] > 0 ? r[i] / diagonal[i] : 0; }); };
  precondition();
  p = z;
  double rz = dot(r, z), rNorm = std::sqrt(dot(r, r));
  if (bNorm == 0) return rNorm == 0 ? 0 : 1;  // no data at all: nothing to fit
  for (int k = 0; k < maxIterations && rNorm > tolerance * bNorm; ++k) {
    system.applyNormal(p, q);
    const double pq = dot(p, q);
    if (!(pq > 0)) break;
    const auto a = static_cast<float>(rz / pq);
    forEach(n, [&](size_t i) {
      x[i] += a * p[i];
      r[i] -= a * q[i];
    });
    precondition();
    const double rzNext = dot(r, z);
    const auto beta = static_cast<float>(rzNext / rz);
    rz = rzNext;
    forEach(n, [&](size_t i) { p[i] = z[i] + beta * p[i]; });
    rNorm = std::sqrt(dot(r, r));
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
