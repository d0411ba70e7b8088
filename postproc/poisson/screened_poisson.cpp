#include "postproc/poisson/screened_poisson.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "postproc/poisson/channel_lanes.h"
#include "postproc/poisson/poisson_system.h"

namespace pathfarm {
namespace {

constexpr size_t kChunk = 16384;  // pixels per chunk of a sum

// Per color channel, the sum over the interleaved vectors of a[i] * b[i].
ChannelSums dot3(const std::vector<float>& a, const std::vector<float>& b) {
  return chunkedSum<3>(a.size() / 3, kChunk,
                       [&](size_t begin, size_t end) { return channelDot(a.data(), b.data(), begin, end); });
}

// The vectors of a solve, kept from one IRLS round to the next: a window's vectors are
// large, and allocating them costs time too. A solve starts with r holding the gradient
// A^T W (A x - b) at its x.
struct Workspace {
  std::vector<float> r, p, q, inverseDiagonal;
};

// One pass over the residual r in chunks: update(begin, end) sets the chunk's values,
// which are then summed while still in cache: returns r.z and r.r per channel, with
// z = D^-1 r. (Updating and summing in one loop would keep the compiler from
// vectorizing either.)
template <class Update>
std::pair<ChannelSums, ChannelSums> updateResiduals(const std::vector<float>& r,
                                                    const std::vector<float>& inverseDiagonal, Update update) {
  const auto sums = chunkedSum<6>(r.size() / 3, kChunk, [&](size_t begin, size_t end) {
    update(begin, end);
    std::array<double, 12> rzLanes{}, rrLanes{};
    forValues(begin, end, [&](size_t i, size_t k) {
      const double rSquared = static_cast<double>(r[i]) * r[i];
      rzLanes[k] += rSquared * inverseDiagonal[i];
      rrLanes[k] += rSquared;
    });
    const ChannelSums rz = channelsOf(rzLanes), rr = channelsOf(rrLanes);
    return std::array<double, 6>{rz[0], rz[1], rz[2], rr[0], rr[1], rr[2]};
  });
  return {{sums[0], sums[1], sums[2]}, {sums[3], sums[4], sums[5]}};
}

// Jacobi-preconditioned conjugate gradients on A^T W A x = A^T W b, from x as given, one
// independent solve per color channel run side by side (scalars per channel). The
// operator returns p.Ap with A p, and an iteration's vector updates take two passes over
// memory: r and the next r.z, r.r; then x (with the previous direction) and the new
// direction. Stops when every channel's |residual| is below the tolerance times its
// `reference` (per channel, squared; the starting residual's when null); returns the
// largest relative residual.
double conjugateGradients(const PoissonSystem& system, std::vector<float>& x, int maxIterations, float tolerance,
                          const ChannelSums* reference, int& iterations, Workspace& workspace) {
  const size_t n = system.size(), pixels = n / 3;
  auto& [r, p, q, inverseDiagonal] = workspace;
  p.resize(n);
  q.resize(n);
  system.inverseDiagonal(inverseDiagonal);
  // r = b - A x is minus the gradient; p = z = D^-1 r.
  ChannelSums rz, rr;
  std::tie(rz, rr) = updateResiduals(r, inverseDiagonal, [&](size_t begin, size_t end) {
    for (size_t i = 3 * begin; i < 3 * end; ++i) {
      r[i] = -r[i];
      p[i] = r[i] * inverseDiagonal[i];
    }
  });
  const ChannelSums bb = reference ? *reference : rr;
  const auto relative = [&] {
    double worst = 0;
    for (size_t c = 0; c < 3; ++c) worst = std::max(worst, bb[c] > 0 ? std::sqrt(rr[c] / bb[c]) : (rr[c] > 0 ? 1 : 0));
    return worst;
  };
  for (int k = 0; k < maxIterations && relative() > tolerance; ++k) {
    const ChannelSums pq = system.applyNormal(p, q);
    std::array<float, 3> a{};
    for (size_t c = 0; c < 3; ++c) a[c] = pq[c] > 0 && rz[c] > 0 ? static_cast<float>(rz[c] / pq[c]) : 0.0f;
    // r -= a q, and the next r.z and r.r.
    const Lanes step = lanesOf(a);
    const auto [nextRz, nextRr] = updateResiduals(r, inverseDiagonal, [&](size_t begin, size_t end) {
      forValues(begin, end, [&](size_t i, size_t k) { r[i] -= step[k] * q[i]; });
    });
    std::array<float, 3> beta{};
    for (size_t c = 0; c < 3; ++c) beta[c] = rz[c] > 0 ? static_cast<float>(nextRz[c] / rz[c]) : 0.0f;
    rz = nextRz;
    rr = nextRr;
    // x += a p, then p = z + beta p.
    const Lanes keep = lanesOf(beta);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, pixels, kChunk), [&](const tbb::blocked_range<size_t>& range) {
      forValues(range.begin(), range.end(), [&](size_t i, size_t k) {
        x[i] += step[k] * p[i];
        p[i] = r[i] * inverseDiagonal[i] + keep[k] * p[i];
      });
    });
    ++iterations;
  }
  return relative();
}

// The smoothing of IRLS round `round` >= 1: geometric from the start epsilon to the final.
float irlsEpsilon(const PoissonSettings& settings, int round) {
  const int reweighted = settings.irlsRounds - 1;
  if (reweighted <= 1) return settings.irlsEpsilon;
  const double t = static_cast<double>(round - 1) / (reweighted - 1);
  return static_cast<float>(settings.irlsStartEpsilon * std::pow(settings.irlsEpsilon / settings.irlsStartEpsilon, t));
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
  if (settings.norm == PoissonNorm::L1 &&
      !(settings.irlsEpsilon > 0 && settings.irlsStartEpsilon >= settings.irlsEpsilon && settings.irlsRounds > 0))
    throw std::invalid_argument("L1 needs IRLS rounds and 0 < epsilon <= start epsilon");
  std::vector<GradientFrame::Color> result(frames.size());
  PoissonStats total;
  PoissonSystem system(frames, settings.alpha);
  std::vector<float> x = system.primal();
  Workspace workspace;
  system.gradient(x, workspace.r);
  double residual = 0;
  if (settings.norm == PoissonNorm::L2) {
    // The tolerance is relative to |A^T b|, the gradient at 0 (computed in the solver's
    // vectors, which it then overwrites).
    workspace.q.assign(x.size(), 0.0f);
    system.gradient(workspace.q, workspace.p);
    const ChannelSums reference = dot3(workspace.p, workspace.p);
    residual = conjugateGradients(system, x, settings.maxIterations, settings.tolerance, &reference, total.iterations,
                                  workspace);
  } else {
    // The first round is the L2 solve; then the weights follow x, with epsilon going down
    // geometrically from irlsStartEpsilon in the first reweighted round to irlsEpsilon in
    // the last. Each round's tolerance is relative to its own starting residual.
    for (int round = 0; round < settings.irlsRounds; ++round) {
      if (round > 0) system.reweightForL1(x, irlsEpsilon(settings, round), workspace.r);
      residual = conjugateGradients(system, x, settings.irlsIterations, settings.tolerance, nullptr, total.iterations,
                                    workspace);
    }
  }
  total.relativeResidual = residual;
  const size_t pixels = frames[0]->pixelCount();
  tbb::parallel_for(size_t{0}, 3 * frames.size(), [&](size_t plane) {
    const size_t f = plane / 3, c = plane % 3;
    auto& values = result[f][c];
    values.resize(pixels);
    for (size_t p = 0; p < pixels; ++p) values[p] = x[3 * (f * pixels + p) + c];
  });
  if (stats) *stats = total;
  return result;
}

}  // namespace pathfarm
