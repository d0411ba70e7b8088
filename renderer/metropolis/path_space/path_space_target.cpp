#include "renderer/metropolis/path_space/path_space_target.h"

#include <stdexcept>

#include "renderer/bidirectional/subpath.h"
#include "renderer/metropolis/path_space/bidirectional_mutation.h"
#include "renderer/metropolis/path_space/caustic_perturbation.h"
#include "renderer/metropolis/path_space/lens_perturbation.h"
#include "renderer/metropolis/path_space/specular_chain.h"
#include "renderer/metropolis/path_space/temporal_perturbation.h"

namespace pathfarm {

PathSpaceTarget::PathSpaceTarget(const WindowScene& scene, double temporalProbability)
    : scene_(scene), temporalProbability_(temporalProbability) {
  if (!scene.camera.isPinhole())
    throw std::invalid_argument("path-space Metropolis (mlt, tmlt) needs a pinhole camera: it never resamples the "
                                "lens point");
  if (!(temporalProbability >= 0 && temporalProbability <= 1))
    throw std::invalid_argument("the temporal mutation probability must lie in [0, 1]");
}

PathSpaceState PathSpaceTarget::bootstrap(int, SampleStream& random) const {
  StreamSource u(random);
  const double tau = scene_.time.fromPrimary(u.next1D());
  const std::optional<WindowInstant> instant = scene_.time.instant(tau);
  if (!instant) return {};
  const BdptScene bdpt = scene_.frame(instant->frame);
  const float time = instant->shutterFraction;
  const Vec2f film{u.next1D() * static_cast<float>(scene_.width()), u.next1D() * static_cast<float>(scene_.height())};
  // Scratch space reused by each thread; its contents never carry over.
  thread_local Subpath cameraPath, lightPath;
  thread_local std::vector<WeightedPath> paths;
  generateCameraSubpath(bdpt, time, film, u.next2D(), u, maxCameraVertices(bdpt), cameraPath);
  generateLightSubpath(bdpt, time, u, maxLightVertices(bdpt), lightPath);
  paths.clear();
  completePathsOf(bdpt, time, cameraPath, lightPath, film, u, paths);
  std::vector<PathSpaceState> states;
  std::vector<double> weights;
  double total = 0;
  for (WeightedPath& p : paths) {
    const double weight = Contribution{0, p.raster, p.contribution}.scalar();
    if (!(weight > 0) || !straightenChains(bdpt, time, p.path.vertices)) continue;
    PathSpaceState state = stateAt(scene_, std::move(p.path), tau);
    if (!(state.density > 0)) continue;
    states.push_back(std::move(state));
    weights.push_back(weight);
    total += weight;
  }
  if (states.empty()) return {};
  double pick = u.next1D() * total;
  size_t chosen = 0;
  while (chosen + 1 < states.size() && pick >= weights[chosen]) pick -= weights[chosen++];
  PathSpaceState seed = std::move(states[chosen]);
  // The seed carries the whole sample's weight, in f's colour (see the header).
  seed.contribution.value = seed.contribution.value * static_cast<float>(total / seed.density);
  return seed;
}

namespace {

// Of the mutations other than the temporal one.
constexpr double kBidirectionalShare = 0.4, kLensShare = 0.3;

}  // namespace

Proposal<PathSpaceState> PathSpaceTarget::propose(const State& current, MutationContext& context) const {
  const double u = context.random.next1D();
  // u past the temporal share, rescaled to [0, 1) over the other mutations.
  const double other = u < temporalProbability_ ? 0 : (u - temporalProbability_) / (1 - temporalProbability_);
  const Kind kind = u < temporalProbability_                   ? kTemporal
                    : other < kBidirectionalShare              ? kBidirectional
                    : other < kBidirectionalShare + kLensShare ? kLens
                                                               : kCaustic;
  PathMutation mutation;
  switch (kind) {
    case kTemporal: mutation = perturbInTime(scene_, current, context).mutation; break;
    case kBidirectional: mutation = bidirectionalMutation(scene_, current, context.random); break;
    case kLens: mutation = lensPerturbation(scene_, current, context.random); break;
    case kCaustic: mutation = causticPerturbation(scene_, current, context.random); break;
  }
  Proposal<State> proposal{std::move(mutation.proposed), kind, 0};
  if (mutation.forward > 0 && current.density > 0)
    proposal.transitionRatio = mutation.reverse / mutation.forward * (current.contribution.scalar() / current.density);
  return proposal;
}

}  // namespace pathfarm
