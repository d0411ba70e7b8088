#pragma once
// One color channel of the screened Poisson problem over a window of frames (Manzi et
// al. 2016, Eq. (2)), as a weighted least-squares system min_I sum_k w_k (A_k I - b_k)^2,
// never assembled: A^T W A is applied row block by row block on the fly. Row blocks, each
// one row per pixel p of frame f (absent rows have weight 0):
//   data      I_f(p)                                  = primal_f(p)      weight alpha^2
//   spatial   I_f(p + x) - I_f(p), I_f(p + y) - I_f(p) = gradient_x/y_f(p)
//   temporal  I_f+1(m(p)) - I_f(p)                     = temporal_f(p)    (m: the target map)
//   mixed     (I_f+1(m(p + x)) - I_f+1(m(p))) - (I_f(p + x) - I_f(p)) = mixed_x_f(p) where
//             m(p + x) = m(p) + x (the motion is locally rigid), and likewise for y
// The transpose gathers through the inverse map m^-1, which exists because the
// correspondence is one-to-one (gradient_frame.h).
#include <array>
#include <cstdint>
#include <vector>

#include "postproc/poisson/gradient_frame.h"

namespace pathfarm {

class PoissonSystem {
 public:
  enum Block { Data, SpatialX, SpatialY, Temporal, MixedX, MixedY, kBlocks };

  // `frames` all have one size; temporal rows of the last frame are left out.
  PoissonSystem(const std::vector<const GradientFrame*>& frames, size_t channel, float alpha);

  size_t size() const { return frames_ * pixels_; }
  // out = A^T W A x.
  void applyNormal(const std::vector<float>& x, std::vector<float>& out) const;
  // A^T W b.
  std::vector<float> rightHandSide() const;
  // The diagonal of A^T W A (Jacobi preconditioner).
  std::vector<float> diagonal() const;
  // Residuals A_k x - b_k of every block (0 for absent rows).
  std::array<std::vector<float>, kBlocks> residuals(const std::vector<float>& x) const;

  // Row weights: the unweighted system's (alpha^2 for data, 1 or 0 elsewhere) times
  // `factors` per block; for iteratively reweighted least squares.
  void setWeightFactors(const std::array<std::vector<float>, kBlocks>& factors);
  const std::vector<float>& baseWeights(Block block) const { return base_[block]; }
  // The data rows' target: the primal images of the window, frame after frame.
  const std::vector<float>& primal() const { return targets_[Data]; }

 private:
  // out = A^T W (A x - s b) with s = 0 or 1: one code path for the operator and the
  // right-hand side.
  void gather(const std::vector<float>& x, bool withTargets, std::vector<float>& out) const;
  void temporalResiduals(const std::vector<float>& x, bool withTargets, std::vector<float>& r) const;

  int width_, height_;
  size_t frames_, pixels_;
  std::vector<int32_t> next_, previous_;  // m and m^-1 as global indices, -1 for none
  std::array<std::vector<float>, 4> targets_;  // data, spatial x, spatial y, temporal
  // A mixed row's residual is the difference of the two temporal rows' residuals plus
  // this (their targets' difference minus the mixed target), per axis.
  std::array<std::vector<float>, 2> mixedShift_;
  std::array<std::vector<float>, kBlocks> base_, weights_;
  // Scratch of gather(), kept between calls: a window's vectors are large.
  mutable std::vector<float> r3_, z_;
};

}  // namespace pathfarm
