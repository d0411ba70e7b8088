#pragma once
// Piecewise-constant densities on [0, 1) and [0, 1)^2, sampled by inverting their
// cumulative distributions (pbrt-v3, Sections 13.3.1 and 13.6.7: Distribution1D/2D). The
// 2D one is a marginal density over rows and, per row, a conditional density over columns.
#include <vector>

#include "renderer/math/vecmath.h"

namespace pathfarm {

class PiecewiseConstant1D {
 public:
  // `values`: non-negative, one per equal-width interval of [0, 1). All zero is allowed:
  // then sample() is uniform and the density is 0 everywhere.
  explicit PiecewiseConstant1D(std::vector<float> values);

  struct Sample {
    float x;       // in [0, 1)
    float pdf;     // density at x
    int interval;  // the interval x lies in
  };
  Sample sample(float u) const;
  float pdf(int interval) const { return integral_ > 0 ? values_[static_cast<size_t>(interval)] / integral_ : 0; }
  int size() const { return static_cast<int>(values_.size()); }
  // Integral of the function over [0, 1): the mean of the values.
  float integral() const { return integral_; }

 private:
  std::vector<float> values_;
  std::vector<float> cdf_;  // size() + 1 entries, 0 first and 1 last
  float integral_ = 0;
};

class PiecewiseConstant2D {
 public:
  // `values` row-major, `width` per row: column x covers [x, x + 1) / width of the first
  // coordinate, row y [y, y + 1) / height of the second.
  PiecewiseConstant2D(const std::vector<float>& values, int width, int height);

  struct Sample {
    Vec2f point;  // in [0, 1)^2
    float pdf;    // density over the unit square
    int column, row;
  };
  Sample sample(Vec2f u) const;
  float pdf(int column, int row) const;
  float integral() const { return marginal_.integral(); }

 private:
  std::vector<PiecewiseConstant1D> conditional_;  // per row, over columns
  PiecewiseConstant1D marginal_;                  // over rows, from the rows' integrals
};

}  // namespace pathfarm
