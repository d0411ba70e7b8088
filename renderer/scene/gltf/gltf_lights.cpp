#include "renderer/scene/gltf/gltf_lights.h"

#include <cmath>

namespace pathfarm {
namespace {

constexpr double kMaxPhotometricIntensity = 1e12;
constexpr double kRightAngle = 1.5707963267948966;
// KHR_lights_punctual gives point and spot lights in candela and directional lights in
// lux; pathfarm renders in radiometric units, converted at the luminous efficacy the
// extension and Blender's exporter and importer all use (docs/gltf.md, "Light units").
constexpr float kWattsPerLumen = 1.0f / 683;

PunctualLight readLight(const GltfDocument& document, int index) {
  const tinygltf::Light& source = document.model().lights[static_cast<size_t>(index)];
  const std::string pointer = "/extensions/KHR_lights_punctual/lights/" + std::to_string(index);
  PunctualLight light;
  light.name = source.name;
  if (source.type == "point") {
    light.type = PunctualType::Point;
  } else if (source.type == "spot") {
    light.type = PunctualType::Spot;
  } else if (source.type == "directional") {
    light.type = PunctualType::Directional;
  } else {
    document.fail(pointer + "/type", "unknown light type \"" + source.type + "\"");
  }
  float color[3] = {1, 1, 1};
  if (!source.color.empty()) {
    if (source.color.size() != 3) document.fail(pointer + "/color", "a colour has three components");
    for (size_t c = 0; c < 3; ++c)
      color[c] = gltfFactor(document, pointer + "/color/" + std::to_string(c), source.color[c], 0, 1e6);
  }
  light.intensity = Rgb(color[0], color[1], color[2]) *
                    (gltfFactor(document, pointer + "/intensity", source.intensity, 0, kMaxPhotometricIntensity) * kWattsPerLumen);
  if (light.type == PunctualType::Spot) {
    const float inner = gltfFactor(document, pointer + "/spot/innerConeAngle", source.spot.innerConeAngle, 0, kRightAngle);
    const float outer = gltfFactor(document, pointer + "/spot/outerConeAngle", source.spot.outerConeAngle, 0, kRightAngle);
    if (!(outer > 0) || !(inner < outer))
      document.fail(pointer + "/spot", "the cone angles need 0 <= innerConeAngle < outerConeAngle <= pi/2");
    light.cosInner = std::cos(inner);
    light.cosOuter = std::cos(outer);
  }
  if (source.range > 0)
    document.warn(pointer + "/range", "range is ignored: the light falls off with the inverse square of distance");
  return light;
}

}  // namespace

void importPunctualLights(const GltfDocument& document, const GltfNodeAnimation& animation,
                          const std::vector<int>& nodes, Scene& scene) {
  const tinygltf::Model& model = document.model();
  for (const int n : nodes) {
    const tinygltf::Node& node = model.nodes[static_cast<size_t>(n)];
    const tinygltf::Value* reference = gltfExtension(node.extensions, "KHR_lights_punctual");
    if (!reference) continue;
    const std::string pointer = gltfPointer("nodes", n) + "/extensions/KHR_lights_punctual/light";
    const double index = gltfNumberOr(*reference, "light", -1);
    if (!(index >= 0 && index < static_cast<double>(model.lights.size())) || index != std::floor(index))
      document.fail(pointer, "the node refers to a light that does not exist");
    PunctualLight light = readLight(document, static_cast<int>(index));
    // Named by its node, as the node places it; the light's own name otherwise.
    if (!node.name.empty()) light.name = node.name;
    if (light.name.empty()) light.name = "light" + std::to_string(n);
    light.transform = animation.worldTransform(n, false);
    scene.punctualLights.push_back(std::move(light));
  }
}

}  // namespace pathfarm
