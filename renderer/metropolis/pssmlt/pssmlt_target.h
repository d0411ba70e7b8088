#pragma once
// Primary-sample-space MLT (Kelemen et al. 2002) over a window of frames, as a target of
// the chain driver. A state is a primary sample vector and a path depth; the path is
// sampled the way pbrt-v3's MLT integrator does it (renderer/bidirectional/
// pssmlt_strategy.h): one bidirectional strategy (s, t) of the state's depth d, chosen
// uniformly among the d + 2, its contribution multiplied by d + 2. The depth is the seed
// strategy: the bootstrap samples every depth, and a chain starts at its seed's depth.
// The chain moves over (depth, primary sample) with density proportional to the
// contribution, which integrates to the normalization b over every depth; large steps
// draw the depth anew. (A chain that kept its seed's depth would give each depth's light
// a share of the chains drawn at random: an error of tens of percent between depths that
// no number of mutations reduces.)
//
// Camera stream: coordinate 0 is the window time (mapped uniformly over the open time,
// window_time.h); from coordinate 1 on, the streams are those of pssmlt_strategy.h.
//
// Mutations: a large step (probability largeStepProbability) renews every coordinate and
// the depth (uniform over 0 ... maxDepth: the proposal stays independent and symmetric);
// of the other steps, temporalStepProbability are temporal steps, which move only the
// time coordinate with the temporal proposal (temporal_proposal.h, asymmetric, so its
// density ratio enters the acceptance), and the rest are small steps (primary_samples.h).
#include "renderer/metropolis/chain_target.h"
#include "renderer/metropolis/pssmlt/primary_samples.h"
#include "renderer/metropolis/window_scene.h"

namespace pathfarm {

struct PssmltState {
  PrimarySamples samples;
  int depth = 0;
  Contribution contribution;
};

class PssmltTarget {
 public:
  using State = PssmltState;
  enum Kind { kLarge, kSmall, kTemporal };

  PssmltTarget(const WindowScene& scene, double largeStepProbability, double temporalStepProbability)
      : scene_(scene), largeStep_(largeStepProbability), temporalStep_(temporalStepProbability) {}

  int strategies() const { return scene_.maxDepth + 1; }
  State bootstrap(int depth, SampleStream& random) const;
  Proposal<State> propose(const State& current, MutationContext& context) const;
  std::vector<std::string> mutationKinds() const { return {"large", "small", "temporal"}; }
  int temporalKind() const { return kTemporal; }

 private:
  // Samples the state's path and sets its contribution.
  void evaluate(State& state, SampleStream& random) const;
  Proposal<State> temporalStep(const State& current, MutationContext& context) const;

  const WindowScene& scene_;
  double largeStep_, temporalStep_;
};

}  // namespace pathfarm
