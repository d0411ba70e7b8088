#include "renderer/metropolis/pssmlt/pssmlt_target.h"

#include <algorithm>

#include "renderer/bidirectional/pssmlt_strategy.h"
#include "renderer/metropolis/pssmlt/primary_source.h"

namespace pathfarm {
namespace {

// The camera stream's first coordinate is the window time; evaluateStrategy reads the
// rest of the stream from the next one on.
constexpr size_t kTime = 0;

}  // namespace

PssmltState PssmltTarget::bootstrap(int depth, SampleStream& random) const {
  State state;
  state.depth = depth;
  evaluate(state, random);
  return state;
}

void PssmltTarget::evaluate(State& state, SampleStream& random) const {
  PrimarySamples& x = state.samples;
  const double tau = scene_.time.fromPrimary(x.get(PrimarySamples::kCamera, kTime, random));
  const std::optional<WindowInstant> instant = scene_.time.instant(tau);
  state.contribution = {};
  if (!instant) return;
  PrimarySource camera(x, PrimarySamples::kCamera, kTime + 1, random);
  PrimarySource light(x, PrimarySamples::kLight, 0, random);
  PrimarySource connection(x, PrimarySamples::kConnection, 0, random);
  // Scratch subpaths, reused by each thread's chains; their contents never carry over.
  thread_local Subpath cameraScratch, lightScratch;
  const StrategyEvaluation path =
      evaluateStrategy(scene_.frame(instant->frame), instant->shutterFraction, state.depth,
                       {camera, light, connection}, cameraScratch, lightScratch);
  state.contribution = {instant->frame, path.raster, path.contribution};
}

Proposal<PssmltState> PssmltTarget::propose(const State& current, MutationContext& context) const {
  const double choice = context.random.next1D();
  const bool large = choice < largeStep_;
  if (!large && choice < largeStep_ + (1 - largeStep_) * temporalStep_) return temporalStep(current, context);
  // A large step draws the depth anew, uniformly: an independent proposal over every
  // (depth, primary sample), so the ratio stays 1 and chains move between depths.
  const int depth = large ? std::min(static_cast<int>(context.random.next1D() * static_cast<float>(strategies())),
                                     strategies() - 1)
                          : current.depth;
  Proposal<State> proposal{{current.samples.nextStep(large), depth, {}}, large ? kLarge : kSmall, 1};
  evaluate(proposal.state, context.random);
  return proposal;
}

Proposal<PssmltState> PssmltTarget::temporalStep(const State& current, MutationContext& context) const {
  Proposal<State> proposal{current, kTemporal, 0};
  PrimarySamples& x = proposal.state.samples;
  const double tau = scene_.time.fromPrimary(x.get(PrimarySamples::kCamera, kTime, context.random));
  const double next = context.temporal.sample(tau, context.random.next1D());
  const double forward = context.temporal.density(tau, next);
  proposal.state.contribution = {};
  // Closed shutter: no path, so the proposal is rejected.
  if (!scene_.time.isOpen(next) || !(forward > 0)) return proposal;
  proposal.transitionRatio = context.temporal.density(next, tau) / forward;
  x.set(PrimarySamples::kCamera, kTime, scene_.time.toPrimary(next), context.random);
  evaluate(proposal.state, context.random);
  return proposal;
}

}  // namespace pathfarm
