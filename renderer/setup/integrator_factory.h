#pragma once
// The integrators, chosen by name: one list that `pathfarm render --integrator` and the
// farm's workers share.
//   pt      path tracing; with a decomposition, its path-space components (Zimmer et al. 2015)
//   bdpt    bidirectional path tracing
//   gpt     gradient-domain path tracing (Kettunen et al. 2015)
//   tgpt    temporal gradient-domain path tracing (Manzi et al. 2016)
//   pssmlt, mlt, tmlt  Metropolis light transport (docs/metropolis.md): Markov chains
//           render windows of frames together, not a frame at a time, so these are built
//           as a MetropolisRenderer (metropolis_renderer.h) by the caller.
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "renderer/integrators/frame_integrator.h"
#include "renderer/integrators/gradient_frame_renderer.h"

namespace pathfarm {

struct IntegratorTraits {
  std::string_view name;
  bool rendersWindows = false;  // the Metropolis integrators
  bool gradient = false;        // gpt, tgpt: differences for a Poisson reconstruction
  bool decomposes = false;      // renders path-space components when asked
  bool temporal = false;        // tgpt, tmlt: correlates each frame with the next
};

const std::vector<IntegratorTraits>& allIntegrators();
std::vector<std::string> integratorNames();
// Throws std::invalid_argument naming the integrators there are.
const IntegratorTraits& integratorNamed(std::string_view name);

// A frame integrator by name: `gradient` applies to gpt and tgpt (tgpt's temporal offset
// frames are on by its name, `gradient.temporal` is ignored). Throws std::invalid_argument for an unknown name, for an
// integrator that renders windows, and for settings the integrator does not support.
std::unique_ptr<FrameIntegrator> makeFrameIntegrator(std::string_view name, const Scene& scene,
                                                     const RenderSettings& settings, GradientSettings gradient = {});

}  // namespace pathfarm
