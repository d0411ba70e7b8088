#pragma once
// Path-space Metropolis light transport (Veach and Guibas 1997) over a window of frames as
// a target of the chain driver (chain_target.h), with the temporal perturbation of Van de
// Woestijne et al. 2017 mixed in.
//
// Bootstrap: one bidirectional sample per bootstrap sample (a window time uniform over the
// open time, a film position uniform over the image, a camera and a light subpath, every
// strategy of their connections, renderer/bidirectional/complete_path.h). Its weight is the
// sum of its strategies' contributions (MIS-weighted f / p, whose mean is the driver's
// normalization b); one strategy's path is chosen in proportion to its contribution, so a
// seed is a path chosen in proportion to its weight, as Veach 1997 (section 11.3.1)
// seeds chains. The seed's specular chains are straightened (specular_chain.h).
//
// The seed's weight is what the driver reads from a bootstrap state's contribution, while
// the chain's density is f(X): a state keeps f*(X) in `density`, and each proposal
// multiplies its transition ratio by contribution.scalar() / density of the current state
// (1 once the chain has moved), so that the driver's acceptance f(Y) T(Y->X) / (weight
// T(X->Y)) becomes f(Y) T(Y->X) / (f(X) T(X->Y)). Splats are value / scalar, the same for
// a weight and for f, which have the same colour.
//
// Mutations: with probability `temporalProbability` the temporal perturbation
// (temporal_perturbation.h); otherwise the bidirectional mutation (40 %,
// bidirectional_mutation.h), the lens perturbation (30 %, lens_perturbation.h) or the
// caustic perturbation (30 %, caustic_perturbation.h): the perturbations explore a
// bright path's neighbourhood with high acceptance, the bidirectional mutation changes
// its length and structure, and, deleting everything after the camera, renews its time.
// Every choice has a fixed probability, which cancels in the acceptance ratio. The
// camera must be a pinhole.
#include "renderer/metropolis/chain_target.h"
#include "renderer/metropolis/path_space/path_state.h"

namespace pathfarm {

class PathSpaceTarget {
 public:
  using State = PathSpaceState;
  enum Kind { kBidirectional, kLens, kCaustic, kTemporal };

  // Throws std::invalid_argument for a thin-lens camera or a probability outside [0, 1].
  PathSpaceTarget(const WindowScene& scene, double temporalProbability);

  int strategies() const { return 1; }
  State bootstrap(int strategy, SampleStream& random) const;
  Proposal<State> propose(const State& current, MutationContext& context) const;
  std::vector<std::string> mutationKinds() const { return {"bidirectional", "lens", "caustic", "temporal"}; }
  int temporalKind() const { return temporalProbability_ > 0 ? kTemporal : -1; }

 private:
  const WindowScene& scene_;
  double temporalProbability_;
};

}  // namespace pathfarm
