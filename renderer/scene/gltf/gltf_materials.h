#pragma once
// glTF materials as pathfarm materials: pbrMetallicRoughness with
// KHR_materials_transmission, KHR_materials_ior and KHR_materials_emissive_strength
// becomes MaterialType::MetallicRoughness; its textures become the scene's textures
// (base colour sRGB-decoded, metallic-roughness as linear data). Features the renderer
// does not model yet are named in a warning, never dropped in silence.
#include <vector>

#include "renderer/scene/gltf/gltf_document.h"
#include "renderer/scene/gltf/gltf_mesh.h"
#include "renderer/scene/scene.h"

namespace pathfarm {

struct GltfMaterials {
  // Per glTF material, its index in Scene::materials, emitted radiance (a factor of the
  // emission texture, an index into Scene::textures or -1) and the texture coordinates
  // its textures read.
  std::vector<int> sceneIndex;
  std::vector<Rgb> emission;
  std::vector<int> emissionTexture;
  std::vector<TextureCoordinates> coordinates;
  // The glTF default material (for primitives without one), added on first use.
  int defaultMaterial(Scene& scene);

 private:
  int default_ = -1;
};

GltfMaterials importMaterials(const GltfDocument& document, Scene& scene);

}  // namespace pathfarm
