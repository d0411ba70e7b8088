#include "postproc/poisson/screened_poisson.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "postproc/poisson/chunked_sum.h"
#include "postproc/poisson/poisson_system.h"

namespace pathfarm {
namespace {

constexpr size_t kChunk = 16384;  // pixels per chunk of a sum

// Per color channel, the sum over the interleaved vectors of a[i] * b[i].
ChannelSums dot3(const std::vector<float>& a, const std::vector<float>& b) {
  return chunkedSum<3>(a.size() / 3, kChunk, [&](size_t begin, size_t end) {
    ChannelSums partial{};
    for (size_t g = begin; g < end; ++g)
      for (size_t c = 0; c < 3; ++c) partial[c] += static_cast<double>(a[3 * g + c]) * b[3 * g + c];
    return partial;
  });
}

// The per-channel scalars of an iteration repeated for 4 pixels: loops over 12
// interleaved values at a time then vectorize.
using Lanes = std::array<float, 12>;

Lanes lanes(const std::array<float, 3>& perChannel) {
  Lanes out{};
  for (size_t k = 0; k < out.size(); ++k) out[k] = perChannel[k % 3];
  return out;
}

// Runs body(i, k) for the values i of pixels [begin, end), k = (i - 3 begin) mod 12, so
// lane k holds channel k mod 3.
template <class Body>
void forValues(size_t begin, size_t end, Body body) {
  size_t i = 3 * begin;
  for (; i + 12 <= 3 * end; i += 12)
    for (size_t k = 0; k < 12; ++k) body(i + k, k);
  for (size_t k = 0; i < 3 * end; ++i, ++k) body(i, k);
}

// Per channel, the sums of 12 lanes (each a channel's), added in lane order.
ChannelSums channelsOf(const std::array<double, 12>& lanes) {
  ChannelSums sums{};
  for (size_t k = 0; k < lanes.size(); ++k) sums[k % 3] += lanes[k];
  return sums;
}

// Jacobi-preconditioned conjugate gradients on A^T W A x = A^T W b, from x as given, one
// independent solve per color channel run side by side (scalars per channel). The
// operator returns p.Ap with A p, and an iteration's vector updates take two passes over
// memory: r and the next r.z, r.r; then x (with the previous direction) and the new
// direction. Stops when every channel's residual is below the tolerance; returns the
// largest relative residual.
// The vectors of a solve, kept from one IRLS round to the next: a window's vectors are
// large, and allocating them costs time too.
struct Workspace {
  std::vector<float> r, p, q, inverseDiagonal;
};

double conjugateGradients(const PoissonSystem& system, std::vector<float>& x, int maxIterations, float tolerance,
                          int& iterations, Workspace& workspace) {
  const size_t n = system.size(), pixels = n / 3;
  auto& [r, p, q, inverseDiagonal] = workspace;
  // |A^T W b| per channel: the gradient at 0 is -A^T W b.
  p.assign(n, 0.0f);
  system.gradient(p, q);
  const ChannelSums bb = dot3(q, q);
  system.inverseDiagonal(inverseDiagonal);
  system.gradient(x, r);
  // r = b - A x is minus the gradient; p = z = D^-1 r.
  const auto start = chunkedSum<6>(pixels, kChunk, [&](size_t begin, size_t end) {
    std::array<double, 6> sums{};
    for (size_t g = begin; g < end; ++g)
      for (size_t c = 0, i = 3 * g; c < 3; ++c, ++i) {
        r[i] = -r[i];
        p[i] = r[i] * inverseDiagonal[i];
        sums[c] += static_cast<double>(r[i]) * p[i];
        sums[3 + c] += static_cast<double>(r[i]) * r[i];
      }
    return sums;
  });
  ChannelSums rz{start[0], start[1], start[2]}, rr{start[3], start[4], start[5]};
  const auto relative = [&] {
    double worst = 0;
    for (size_t c = 0; c < 3; ++c) worst = std::max(worst, bb[c] > 0 ? std::sqrt(rr[c] / bb[c]) : (rr[c] > 0 ? 1 : 0));
    return worst;
  };
  for (int k = 0; k < maxIterations && relative() > tolerance; ++k) {
    const ChannelSums pq = system.applyNormal(p, q);
    std::array<float, 3> a{};
    for (size_t c = 0; c < 3; ++c) a[c] = pq[c] > 0 && rz[c] > 0 ? static_cast<float>(rz[c] / pq[c]) : 0.0f;
    // r -= a q, and the next r.z and r.r with z = D^-1 r.
    const Lanes step = lanes(a);
    const auto sums = chunkedSum<6>(pixels, kChunk, [&](size_t begin, size_t end) {
      std::array<double, 12> rzLanes{}, rrLanes{};
      forValues(begin, end, [&](size_t i, size_t k) {
        r[i] -= step[k] * q[i];
        const double rSquared = static_cast<double>(r[i]) * r[i];
        rzLanes[k] += rSquared * inverseDiagonal[i];
        rrLanes[k] += rSquared;
      });
      const ChannelSums rzPart = channelsOf(rzLanes), rrPart = channelsOf(rrLanes);
      return std::array<double, 6>{rzPart[0], rzPart[1], rzPart[2], rrPart[0], rrPart[1], rrPart[2]};
    });
    std::array<float, 3> beta{};
    for (size_t c = 0; c < 3; ++c) {
      beta[c] = rz[c] > 0 ? static_cast<float>(sums[c] / rz[c]) : 0.0f;
      rz[c] = sums[c];
      rr[c] = sums[3 + c];
    }
    // x += a p, then p = z + beta p.
    const Lanes keep = lanes(beta);
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
  Workspace workspace;
  double residual = 0;
  if (settings.norm == PoissonNorm::L2) {
    residual = conjugateGradients(system, x, settings.maxIterations, settings.tolerance, total.iterations, workspace);
  } else {
    residual = conjugateGradients(system, x, settings.irlsIterations, settings.tolerance, total.iterations, workspace);
    for (int round = 1; round < settings.irlsRounds; ++round) {
      system.reweightForL1(x, settings.irlsEpsilon);
      residual =
          conjugateGradients(system, x, settings.irlsIterations, settings.tolerance, total.iterations, workspace);
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
