#pragma once
// A scene as loaded from its JSON file (docs/scene-format.md): camera, materials,
// shapes with their animation, emitters and the render defaults.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "renderer/lights/environment_light.h"
#include "renderer/lights/punctual_light.h"
#include "renderer/materials/material.h"
#include "renderer/scene/alpha_coverage.h"
#include "renderer/math/animation.h"
#include "renderer/scene/camera.h"
#include "renderer/scene/mesh.h"
#include "renderer/scene/mesh_deformation.h"
#include "renderer/scene/texture.h"

namespace pathfarm {

enum class ShapeType { Sphere, Rectangle, Box, Mesh };

struct SceneObject {
  std::string name;
  uint32_t objectId = 0;  // stable across frames and runs; written to the objectid buffers
  ShapeType type = ShapeType::Mesh;
  float radius = 1;  // spheres: centered at the object-space origin
  std::shared_ptr<const TriangleMesh> mesh;  // rectangles, boxes and meshes
  int material = 0;  // index into Scene::materials
  Rgb emission;      // radiance emitted from the front side (outward normal); black if none
  int emissionTexture = -1;  // into Scene::textures: emission is multiplied by it at the hit's uv
  AnimatedTrs transform;  // object to world
  // Vertices that move on their own (skins, morph targets); then `transform` is the
  // identity and the deformation's poses are in world space.
  std::shared_ptr<const MeshDeformation> deformation;

  bool isEmitter() const { return !emission.isBlack(); }
  // Whether the object's surface moves during the shot, rigidly or not.
  bool moves() const { return transform.isAnimated() || deformation; }
};

struct RenderDefaults {
  int width = 320, height = 240;
  int spp = 16;
  int maxDepth = 8;  // scattering events per path; 1 is direct lighting only
  int frameStart = 0, frameEnd = 0;
};

struct Scene {
  std::filesystem::path file;
  double fps = 24;
  uint64_t seed = 0;
  // Beckmann alpha below which a glossy lobe counts as specular (R/T) rather than D.
  float roughnessThreshold = 0.1f;
  CameraDesc camera;
  std::vector<std::string> materialNames;
  std::vector<Material> materials;
  std::vector<ImageTexture> textures;
  std::vector<AlphaCoverage> coverages;  // cut-outs, indexed by Material::coverage
  std::vector<SceneObject> objects;
  EnvironmentLight environment;  // black if none
  std::vector<PunctualLight> punctualLights;
  RenderDefaults defaults;

  // The time in seconds of a point `shutterFraction` of the way through frame `frame`'s
  // shutter interval.
  double timeAt(int64_t frame, float shutterFraction) const {
    const float open = camera.shutterOpen, close = camera.shutterClose;
    return (static_cast<double>(frame) + open + shutterFraction * (close - open)) / fps;
  }
};

// The radiance `object` emits at surface coordinates `uv` (from its front side).
inline Rgb emissionAt(const Scene& scene, const SceneObject& object, Vec2f uv) {
  if (object.emissionTexture < 0) return object.emission;
  return object.emission * scene.textures[static_cast<size_t>(object.emissionTexture)].lookup(uv);
}

}  // namespace pathfarm
