#pragma once
// The screened Poisson problem over a window of frames (Manzi et al. 2016, Eq. (2)), as a
// weighted least-squares system min_I sum_k w_k (A_k I - b_k)^2 per color channel, never
// assembled: A^T W A is applied row block by row block on the fly. The three channels
// are solved side by side (unknowns interleaved R, G, B per pixel), so the row structure
// is read once for all three. Row blocks, each one row per pixel p of frame f (absent
// rows have weight 0):
//   data      I_f(p)                                  = primal_f(p)      weight alpha^2
//   spatial   I_f(p + x) - I_f(p), I_f(p + y) - I_f(p) = gradient_x/y_f(p)
//   temporal  I_f+1(m(p)) - I_f(p)                     = temporal_f(p)    (m: the target map)
//   mixed     (I_f+1(m(p + x)) - I_f+1(m(p))) - (I_f(p + x) - I_f(p)) = mixed_x_f(p) where
//             m(p + x) = m(p) + x (the motion is locally rigid), and likewise for y
// The transpose gathers through the inverse map m^-1, which exists because the
// correspondence is one-to-one (gradient_frame.h). A row with a non-finite value in any
// channel constrains nothing.
// Rows are weighted by their confidence 1 / (1 + v / (K v_mean)), with v the variance of
// the row's target (its layer's, summed over channels), v_mean the mean of v over the
// block's rows in the window and K = kOutlierVarianceRatio: close to 1 for typical rows,
// and like inverse-variance weighting for an outlier (a replayed path that found the sun
// gives a temporal row far off its neighbours, with a variance thousands of times the
// typical one). K keeps typical rows near 1 because a sample variance grows with the
// sampled value: weighting every row by it would pull the image down (the sky furnace,
// tests/renderer/integrators/gradient_render_test.cpp, sees it at K = 1). Without a
// variance layer, or where every variance is 0, the confidence is 1.
#include <array>
#include <cstdint>
#include <vector>

#include "postproc/poisson/bfloat16.h"
#include "postproc/poisson/chunked_sum.h"
#include "postproc/poisson/gradient_frame.h"

namespace pathfarm {

class PoissonSystem {
 public:
  static constexpr double kOutlierVarianceRatio = 16;  // a row this far above the mean weighs 1/2

  enum Block { Data, SpatialX, SpatialY, Temporal, MixedX, MixedY, kBlocks };

  // `frames` all have one size; temporal rows of the last frame are left out.
  PoissonSystem(const std::vector<const GradientFrame*>& frames, float alpha);

  // Unknowns: 3 per pixel of every frame, index 3 * (frame * pixels + pixel) + channel.
  size_t size() const { return 3 * rows_; }
  // out = A^T W A x; returns <x, out> per channel (summed in a fixed order, so the same
  // bits for any thread count): conjugate gradients need it and get it without another
  // pass over memory.
  ChannelSums applyNormal(const std::vector<float>& x, std::vector<float>& out) const;
  // out = A^T W (A x - b): the gradient of half the weighted least-squares objective,
  // minus the residual of the normal equations, in one pass.
  void gradient(const std::vector<float>& x, std::vector<float>& out) const;
  // out = 1 / the diagonal of A^T W A (the Jacobi preconditioner), 0 for an unknown no
  // row constrains.
  void inverseDiagonal(std::vector<float>& out) const;
  // Residuals A_k x - b_k of every block, indexed like the unknowns (0 for absent rows).
  std::array<std::vector<float>, kBlocks> residuals(const std::vector<float>& x) const;

  // Iteratively reweighted least squares for the L1 norm: every row's weight becomes the
  // unweighted system's (alpha^2 for data, 1 elsewhere) times its confidence times
  // 1 / max(|scaled residual|, epsilon) at x, the scaled residual being alpha times it for
  // data rows. A row's squared error then equals its confidence times its absolute error
  // at x (up to the factors' rounding to bfloat16).
  // In the same pass, `gradient` becomes the gradient at x under the new weights.
  void reweightForL1(const std::vector<float>& x, float epsilon, std::vector<float>& gradient);
  // The data rows' target: the primal images of the window, indexed like the unknowns.
  const std::vector<float>& primal() const { return targets_[Data]; }

 private:
  bool present(Block block, size_t row) const { return (presence_[row] >> block) & 1u; }
  // The weight of block's row for the unknown i (index 3 * row + channel).
  float weight(Block block, size_t i) const {
    return (block == Data ? alphaSquared_ : 1.0f) * fromBfloat16(factors_[block][i]);
  }
  // Weights computed from the residuals during a pass (reweightForL1), written to `factors`.
  struct Reweighting {
    float epsilon;
    std::array<uint16_t*, kBlocks> factors;
  };
  // out = A^T W (A x - b) with the targets b, or A^T W A x without them: one code path
  // for the operator, the gradient and the reweighting. Returns <x, out> per channel.
  template <bool kWithTargets>
  ChannelSums gather(const std::vector<float>& x, std::vector<float>& out,
                     const Reweighting* reweighting = nullptr) const;
  // One gather() pass over the window's lines (poisson_system.cpp).
  template <bool kWithTargets>
  class LinePass;
  // Sets confidence_ from the frames' variance layers (present rows only).
  void weighByVariance(const std::vector<const GradientFrame*>& frames);
  // The temporal row g's A x - b in channel c, 0 where it is absent.
  float temporalResidual(const std::vector<float>& x, size_t g, size_t c) const;

  int width_, height_;
  size_t frames_, pixels_, rows_;              // rows_: pixels of the window (rows of one block)
  std::vector<int32_t> next_, previous_;       // m and m^-1 as window pixel indices, -1 for none
  std::array<std::vector<float>, 4> targets_;  // data, spatial x, spatial y, temporal (3 per row)
  // A mixed row's residual is the difference of the two temporal rows' residuals plus
  // this (their targets' difference minus the mixed target), per axis (3 per row).
  std::array<std::vector<float>, 2> mixedShift_;
  float alpha_, alphaSquared_;
  std::vector<uint8_t> presence_;                    // per row, bit k: block k's row exists
  // A row's weight is the unweighted system's (alpha^2 for data, 1 elsewhere) times its
  // factor: its confidence, times the IRLS factor after reweightForL1; 0 for an absent
  // row. bfloat16 (bfloat16.h), per row and channel: the operator reads them on every pass.
  std::array<std::vector<uint16_t>, kBlocks> factors_;
  // The confidence of every row (above; 0 for an absent row), bfloat16, one per row.
  std::array<std::vector<uint16_t>, kBlocks> confidence_;
  // Scratch of gather(), kept between calls: a window's vectors are large.
  mutable std::vector<float> z_;
};

}  // namespace pathfarm
