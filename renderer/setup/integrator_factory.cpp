#include "renderer/setup/integrator_factory.h"

#include <stdexcept>
#include <string>

#include "renderer/bidirectional/bdpt_frame_renderer.h"
#include "renderer/integrators/frame_renderer.h"

namespace pathfarm {

const std::vector<IntegratorTraits>& allIntegrators() {
  static const std::vector<IntegratorTraits> integrators = {
      {.name = "pt", .decomposes = true},
      {.name = "bdpt"},
      {.name = "gpt", .gradient = true},
      {.name = "tgpt", .gradient = true, .temporal = true},
      {.name = "pssmlt", .rendersWindows = true},
      {.name = "mlt", .rendersWindows = true},
      {.name = "tmlt", .rendersWindows = true, .temporal = true},
  };
  return integrators;
}

std::vector<std::string> integratorNames() {
  std::vector<std::string> names;
  for (const IntegratorTraits& traits : allIntegrators()) names.emplace_back(traits.name);
  return names;
}

const IntegratorTraits& integratorNamed(std::string_view name) {
  for (const IntegratorTraits& traits : allIntegrators())
    if (traits.name == name) return traits;
  std::string names;
  for (const std::string& known : integratorNames()) names += (names.empty() ? "" : ", ") + known;
  throw std::invalid_argument("no integrator is named \"" + std::string(name) + "\" (there are: " + names + ")");
}

std::unique_ptr<FrameIntegrator> makeFrameIntegrator(std::string_view name, const Scene& scene,
                                                     const RenderSettings& settings, GradientSettings gradient) {
  const IntegratorTraits& traits = integratorNamed(name);
  if (traits.rendersWindows)
    throw std::invalid_argument("--integrator " + std::string(name) + " renders windows of frames, not frames");
  if (settings.decomposition && !traits.decomposes)
    throw std::invalid_argument("--integrator " + std::string(name) + " renders no path-space components");
  if (traits.gradient) {
    gradient.temporal = traits.temporal;
    return std::make_unique<GradientFrameRenderer>(scene, settings, gradient);
  }
  if (name == "bdpt") return std::make_unique<BdptFrameRenderer>(scene, settings);
  return std::make_unique<FrameRenderer>(scene, settings);
}

}  // namespace pathfarm
