#pragma once
// KHR_lights_punctual: the point, spot and directional lights that nodes of the rendered
// scene carry, placed (and animated) by their nodes, into Scene::punctualLights.
#include <vector>

#include "renderer/scene/gltf/gltf_animation.h"
#include "renderer/scene/scene.h"

namespace pathfarm {

void importPunctualLights(const GltfDocument& document, const GltfNodeAnimation& animation,
                          const std::vector<int>& nodes, Scene& scene);

}  // namespace pathfarm
