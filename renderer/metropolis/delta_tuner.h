#pragma once
// Tunes the temporal perturbation's reach D towards a target acceptance rate (about 23 %
// is the usual rule, Van de Woestijne et al. 2017, after Roberts et al. 1997) during the
// first part of a chain, then freezes it.
//
// The rule: after the n-th temporal proposal of the tuning part, with acceptance
// probability a_n,  log D <- log D + (a_n - target) / sqrt(n), with D kept within
// [1e-3, window length] frames. A low acceptance shrinks D, a high one grows it, with
// steps that shrink so D settles. It reads only the chain's own history, so the tuned D
// is a deterministic function of the chain. After the tuning part D stays fixed and the
// chain is an ordinary Metropolis-Hastings chain; the tuning part's splats are kept (the
// chain's start-up bias is of the same order as MLT's usual one).
#include <cstdint>

namespace pathfarm {

class DeltaTuner {
 public:
  // Tunes during the first `tuningMutations` mutations when `enabled`.
  DeltaTuner(double initialDelta, double windowLength, bool enabled, double target, uint64_t tuningMutations);

  double delta() const { return delta_; }
  bool tuning(uint64_t mutation) const { return enabled_ && mutation < tuningMutations_; }
  // Reports a temporal proposal's acceptance probability at mutation `mutation`.
  void observe(uint64_t mutation, double acceptance);

 private:
  double delta_, maxDelta_, target_;
  bool enabled_;
  uint64_t tuningMutations_;
  uint64_t observed_ = 0;
};

}  // namespace pathfarm
