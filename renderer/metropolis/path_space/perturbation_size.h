#pragma once
// The size of Veach's perturbations (Veach 1997, section 11.4.3): a distance r between
// r1 and r2 with density proportional to 1 / r (uniform in log r), in a direction uniform
// around the current point. The proposal density depends only on the distance between
// the two points, so it is symmetric and the same both ways.
#include <cmath>

#include "renderer/math/vecmath.h"

namespace pathfarm {

class PerturbationSize {
 public:
  PerturbationSize(double r1, double r2) : r1_(r1), r2_(r2), logRatio_(std::log(r2 / r1)) {}

  // A distance for a uniform u in [0, 1).
  double sample(double u) const { return r1_ * std::exp(u * logRatio_); }
  // The density of the distance r (per unit of r).
  double density(double r) const { return r >= r1_ && r <= r2_ ? 1 / (r * logRatio_) : 0; }

 private:
  double r1_, r2_, logRatio_;
};

}  // namespace pathfarm
