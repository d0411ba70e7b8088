#pragma once
// What a Markov chain of the chain driver (chain_driver.h) samples. A target is a class
// with:
//
//   using State = ...;            // copyable; holds `Contribution contribution`
//   int strategies() const;       // seed strategies per bootstrap sample (e.g. depths)
//   State bootstrap(int strategy, SampleStream& random) const;
//                                 // an independent sample over the window's open time,
//                                 // drawing only from `random` (so it can be regenerated)
//   Proposal<State> propose(const State& current, MutationContext& context) const;
//   std::vector<std::string> mutationKinds() const;
//   int temporalKind() const;     // index in mutationKinds() of the temporal mutation, or -1
//
// The chain's stationary density is proportional to the contribution's scalar(), over
// the measure the bootstrap samples from (primary sample space for PSSMLT, path space
// with area measure for path-space MLT).
#include <concepts>
#include <cstdint>
#include <string>
#include <vector>

#include "renderer/math/vecmath.h"
#include "renderer/metropolis/temporal_proposal.h"
#include "renderer/sampling/sample_stream.h"

namespace pathfarm {

// Where a state lands on the film and with what value: `value` is the estimate whose
// mean over the bootstrap's measure, restricted to a pixel of a frame, is that pixel's
// radiance times the number of pixels and frames (the film position and the time being
// uniform over image and open time).
struct Contribution {
  int64_t frame = 0;
  Vec2f film;  // continuous pixel position
  Rgb value;

  // The scalar the chain's density is proportional to (f* of Kelemen et al. 2002).
  double scalar() const { return value.isFinite() ? static_cast<double>(value.luminance()) : 0.0; }
};

template <class State>
struct Proposal {
  State state;
  int kind = 0;
  // T(proposed -> current) / T(current -> proposed); 1 for symmetric mutations.
  double transitionRatio = 1;
};

// What a target may use while proposing: the chain's random stream and the temporal
// proposal with the chain's current reach D.
struct MutationContext {
  SampleStream& random;
  const TemporalProposal& temporal;
};

template <class T>
concept ChainTarget = requires(const T& target, const typename T::State& state, SampleStream& random,
                               MutationContext& context) {
  { state.contribution } -> std::convertible_to<Contribution>;
  { target.strategies() } -> std::convertible_to<int>;
  { target.bootstrap(0, random) } -> std::same_as<typename T::State>;
  { target.propose(state, context) } -> std::same_as<Proposal<typename T::State>>;
  { target.mutationKinds() } -> std::same_as<std::vector<std::string>>;
  { target.temporalKind() } -> std::convertible_to<int>;
};

}  // namespace pathfarm
