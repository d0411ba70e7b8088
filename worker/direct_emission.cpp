#include "worker/direct_emission.h"

#include <algorithm>

#include "postproc/filters/decomposed_frame.h"
#include "renderer/decomposition/effective_irradiance.h"

namespace pathfarm::farm {
namespace {

constexpr const char* kRgb[3] = {"R", "G", "B"};

std::vector<std::string> componentsOf(const FrameImage& frame) {
  std::vector<std::string> components = decompositionComponents(frame);
  if (components.empty()) throw std::invalid_argument("the frame has no pathfarm.decomposition attribute");
  return components;
}

// Adds `sign` times the light to the beauty and the components' colors, and recomputes
// their irradiance from the colors where the frame has it.
void apply(FrameImage& frame, const FrameImage& emission, float sign, const std::vector<uint8_t>* only) {
  for (const std::string& component : componentsOf(frame)) {
    for (const char* c : kRgb) {
      const std::string direct = component + ".direct." + c;
      if (!emission.hasChannel(direct)) continue;
      const std::vector<float>& light = emission.channel(direct);
      std::vector<float>& beauty = frame.channel(c);
      std::vector<float>& color = frame.channel(component + ".color." + c);
      const std::string irradianceName = component + ".irradiance." + c;
      std::vector<float>* irradiance = frame.hasChannel(irradianceName) ? &frame.channel(irradianceName) : nullptr;
      const std::vector<float>* reflectance =
          irradiance ? &frame.channel(component + ".reflectance." + c) : nullptr;
      for (size_t p = 0; p < light.size(); ++p) {
        if (light[p] == 0.0f || (only && !(*only)[p])) continue;
        beauty[p] += sign * light[p];
        color[p] = std::max(0.0f, color[p] + sign * light[p]);
        if (irradiance) (*irradiance)[p] = effectiveIrradiance(color[p], (*reflectance)[p]);
      }
    }
  }
}

}  // namespace

FrameImage takeDirectEmission(FrameImage& frame) {
  FrameImage emission(frame.width(), frame.height());
  for (const std::string& component : componentsOf(frame)) {
    for (const char* c : kRgb) {
      const std::vector<float>& color = frame.channel(component + ".color." + c);
      const std::vector<float>& emitted = frame.channel(component + ".emission." + c);
      if (std::all_of(emitted.begin(), emitted.end(), [](float v) { return v <= 0.0f; })) continue;
      std::vector<float>& light = emission.addChannel(component + ".direct." + c);
      // The light is part of the color; the clamp only guards against rounding.
      for (size_t p = 0; p < light.size(); ++p) light[p] = std::clamp(emitted[p], 0.0f, std::max(0.0f, color[p]));
    }
  }
  apply(frame, emission, -1.0f, nullptr);
  return emission;
}

void addDirectEmission(FrameImage& frame, const FrameImage& emission, const std::vector<uint8_t>* only) {
  apply(frame, emission, 1.0f, only);
}

}  // namespace pathfarm::farm
