#pragma once
// Loads a glTF 2.0 scene (.gltf or .glb) as a pathfarm Scene: the chosen scene's node
// hierarchy with its animation, mesh primitives as triangle meshes (a mesh used by many
// nodes is shared, not copied), metallic-roughness materials, emissive surfaces as area
// lights and a perspective camera. See docs/gltf.md for what is supported and what is
// refused.
#include <filesystem>
#include <string>

#include "renderer/scene/scene.h"

namespace pathfarm {

struct GltfImportOptions {
  double fps = 24;          // turns the animation's seconds into frames
  std::string sceneName;    // empty: the file's default scene (or its first)
  std::string cameraName;   // a camera's or its node's name; empty: the first camera found
  bool requireCamera = true;  // false when the including JSON scene supplies the camera
};

class GltfDocument;

// Throws SceneError naming the file and the JSON pointer of what is wrong.
Scene loadGltfScene(const std::filesystem::path& file, const GltfImportOptions& options = {});
Scene importGltfScene(const GltfDocument& document, const GltfImportOptions& options = {});

bool isGltfFile(const std::filesystem::path& file);

}  // namespace pathfarm
