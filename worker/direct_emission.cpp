#include "worker/direct_emission.h"

#include <algorithm>

#include "renderer/decomposition/decomposition.h"
#include "renderer/decomposition/effective_irradiance.h"

namespace pathfarm::farm {
namespace {

constexpr const char* kRgb[3] = {"R", "G", "B"};

// The component whose color receives emission met at the first vertex.
std::string emissionComponent(const FrameImage& frame) {
  const auto described = frame.attributes().find("pathfarm.decomposition");
  if (described == frame.attributes().end())
    throw std::invalid_argument("the frame has no pathfarm.decomposition attribute");
  const Decomposition decomposition = Decomposition::parse(described->second);
  const LpeAutomaton& automaton = decomposition.automaton();
  return decomposition.name(automaton.accepting(automaton.next(automaton.initial(), PathSymbol::E)));
}

// Adds `sign` times the emission to the beauty and the component's color, and recomputes
// the component's irradiance from its color.
void apply(FrameImage& frame, const std::string& component, const FrameImage& emission, float sign) {
  for (const char* c : kRgb) {
    const std::vector<float>& light = emission.channel(std::string("direct_emission.") + c);
    std::vector<float>& beauty = frame.channel(c);
    std::vector<float>& color = frame.channel(component + ".color." + c);
    std::vector<float>& irradiance = frame.channel(component + ".irradiance." + c);
    const std::vector<float>& reflectance = frame.channel(component + ".reflectance." + c);
    for (size_t p = 0; p < light.size(); ++p) {
      beauty[p] += sign * light[p];
      color[p] = std::max(0.0f, color[p] + sign * light[p]);
      irradiance[p] = effectiveIrradiance(color[p], reflectance[p]);
    }
  }
}

}  // namespace

FrameImage takeDirectEmission(FrameImage& frame) {
  const std::string component = emissionComponent(frame);
  FrameImage emission(frame.width(), frame.height());
  for (const char* c : kRgb) {
    const std::vector<float>& color = frame.channel(component + ".color." + c);
    const std::vector<float>& emitted = frame.channel(component + ".emission." + c);
    std::vector<float>& light = emission.addChannel(std::string("direct_emission.") + c);
    for (size_t p = 0; p < light.size(); ++p) light[p] = std::clamp(emitted[p], 0.0f, std::max(0.0f, color[p]));
  }
  apply(frame, component, emission, -1.0f);
  return emission;
}

void addDirectEmission(FrameImage& frame, const FrameImage& emission) {
  apply(frame, emissionComponent(frame), emission, 1.0f);
}

}  // namespace pathfarm::farm
