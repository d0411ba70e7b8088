#include "renderer/scene/scene_loader.h"

#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "renderer/scene/gltf/gltf_scene.h"
#include "renderer/scene/mesh_io.h"
#include "renderer/scene/scene_inputs.h"
#include "renderer/scene/scene_parsers.h"

namespace pathfarm {
namespace {

void parseRender(const JsonNode& node, RenderDefaults& defaults) {
  node.expectKeys({"resolution", "spp", "max_depth", "frames"});
  if (auto res = node.optional("resolution")) {
    const auto e = res->elements();
    if (e.size() != 2) res->fail("expected [width, height]");
    defaults.width = e[0].integer(1, 16384);
    defaults.height = e[1].integer(1, 16384);
  }
  if (auto spp = node.optional("spp")) defaults.spp = spp->integer(1, 1 << 20);
  if (auto depth = node.optional("max_depth")) defaults.maxDepth = depth->integer(0, 1024);
  if (auto frames = node.optional("frames")) {
    const auto e = frames->elements();
    if (e.size() != 2) frames->fail("expected [first, last]");
    defaults.frameStart = e[0].integer(0, 10'000'000);
    defaults.frameEnd = e[1].integer(defaults.frameStart, 10'000'000);
  }
}

void parseShutter(const JsonNode& node, CameraDesc& camera) {
  const auto e = node.elements();
  if (e.size() != 2) node.fail("expected [open, close] as fractions of a frame");
  camera.shutterOpen = static_cast<float>(e[0].number(0, 1));
  camera.shutterClose = static_cast<float>(e[1].number(camera.shutterOpen, 1));
}

void parseCamera(const JsonNode& node, double fps, CameraDesc& camera) {
  node.expectKeys({"position", "look_at", "up", "fov", "aperture_radius", "focus_distance",
                   "shutter", "animation"});
  const Vec3f eye = node["position"].vec3(-kMaxCoordinate, kMaxCoordinate);
  const Vec3f target = node["look_at"].vec3(-kMaxCoordinate, kMaxCoordinate);
  const Vec3f up = node.has("up") ? node["up"].vec3() : Vec3f{0, 1, 0};
  if (length(target - eye) < 1e-6f) node["look_at"].fail("look_at must differ from position");
  const Vec3f back = normalize(eye - target);
  if (length(up) < 1e-6f || length(cross(normalize(up), back)) < 1e-4f)
    node.fail("up must not be zero or parallel to the viewing direction");
  const Vec3f right = normalize(cross(up, back));
  const Quaternion orientation = Quaternion::fromBasis(right, cross(back, right), back);
  camera.transform = AnimatedTrs(Trs{eye, Quaternion{}, {1, 1, 1}});

  if (auto fov = node.optional("fov")) camera.fovDegrees = static_cast<float>(fov->number(0.01, 179));
  if (auto a = node.optional("aperture_radius"))
    camera.apertureRadius = static_cast<float>(a->number(0, 1e6));
  camera.focusDistance = length(target - eye);
  if (auto f = node.optional("focus_distance"))
    camera.focusDistance = static_cast<float>(f->number(1e-6, 1e9));
  if (auto shutter = node.optional("shutter")) parseShutter(*shutter, camera);
  if (auto animation = node.optional("animation")) {
    // A camera moves and turns but never scales.
    animation->expectKeys({"translate", "rotate"});
    parseAnimation(*animation, fps, camera.transform);
  }
  // Rotation keys turn the look-at view about the camera's own position.
  camera.transform.rotateAfter(orientation);
}

std::shared_ptr<const TriangleMesh> parseShapeGeometry(const JsonNode& node, ShapeType type,
                                                       const std::filesystem::path& folder) {
  const float maxSize = 1e7f;
  switch (type) {
    case ShapeType::Rectangle: {
      const auto e = node["size"].elements();
      if (e.size() != 2) node["size"].fail("expected [width, height]");
      return std::make_shared<TriangleMesh>(makeRectangle(
          static_cast<float>(e[0].number(1e-6, maxSize)), static_cast<float>(e[1].number(1e-6, maxSize))));
    }
    case ShapeType::Box:
      return std::make_shared<TriangleMesh>(makeBox(node["size"].vec3(1e-6f, maxSize)));
    case ShapeType::Mesh: {
      const JsonNode file = node["file"];
      try {
        return std::make_shared<TriangleMesh>(loadMesh(folder / file.string()));
      } catch (const MeshError& e) {
        file.fail(e.what());
      }
    }
    case ShapeType::Sphere:
      break;
  }
  return nullptr;
}

ShapeType parseShapeType(const JsonNode& node) {
  static const std::map<std::string, ShapeType> types{{"sphere", ShapeType::Sphere},
                                                      {"rectangle", ShapeType::Rectangle},
                                                      {"box", ShapeType::Box},
                                                      {"mesh", ShapeType::Mesh}};
  const std::string name = node.string();
  const auto it = types.find(name);
  if (it == types.end())
    node.fail("unknown shape type \"" + name + "\" (expected sphere, rectangle, box or mesh)");
  return it->second;
}

SceneObject parseShape(const JsonNode& node, size_t index, const Scene& scene,
                       const std::map<std::string, int>& materialIndex,
                       const std::filesystem::path& folder) {
  SceneObject object;
  object.type = parseShapeType(node["type"]);
  std::vector<const char*> keys{"type", "name", "object_id", "material", "emission", "transform",
                                "animation"};
  keys.push_back(object.type == ShapeType::Sphere ? "radius"
                 : object.type == ShapeType::Mesh ? "file"
                                                  : "size");
  node.expectKeys(keys);

  object.name = node.has("name") ? node["name"].string() : "shape" + std::to_string(index);
  object.objectId = node.has("object_id") ? static_cast<uint32_t>(node["object_id"].integer(1, 1 << 30))
                                          : static_cast<uint32_t>(index + 1);
  const JsonNode material = node["material"];
  const std::string name = material.string();
  const auto it = materialIndex.find(name);
  if (it == materialIndex.end()) material.fail("unknown material \"" + name + "\"");
  object.material = it->second;
  if (auto e = node.optional("emission")) object.emission = e->rgb(0, 1e9);

  if (object.type == ShapeType::Sphere) {
    object.radius = static_cast<float>(node["radius"].number(1e-6, 1e7));
  } else {
    object.mesh = parseShapeGeometry(node, object.type, folder);
  }
  object.transform = AnimatedTrs(node.has("transform") ? parseTrs(node["transform"]) : Trs{});
  if (auto animation = node.optional("animation")) parseAnimation(*animation, scene.fps, object.transform);
  if (object.type == ShapeType::Sphere) {
    // Spheres are intersected analytically and must stay spheres.
    for (const Vec3f& s : object.transform.allScales()) {
      if (s.x != s.y || s.y != s.z) node.fail("a sphere can only be scaled uniformly");
    }
  }
  return object;
}

// "include": "file.glb" | {"file": ..., "scene": name, "camera": name, "shutter": [open,
// close]}: the glTF scene the JSON file then adds to and overrides.
Scene parseInclude(const JsonNode& node, const std::filesystem::path& folder, double fps, bool hasCamera) {
  GltfImportOptions options;
  options.fps = fps;
  options.requireCamera = !hasCamera;
  if (node.isObject()) {
    node.expectKeys({"file", "scene", "camera", "shutter"});
    if (auto name = node.optional("scene")) options.sceneName = name->string();
    if (auto name = node.optional("camera")) {
      if (hasCamera) name->fail("give the camera either here or as \"camera\", not both");
      options.cameraName = name->string();
    }
  }
  const JsonNode file = node.isObject() ? node["file"] : node;
  const std::filesystem::path path = folder / file.string();
  if (!isGltfFile(path)) file.fail("an included scene must be a .gltf or .glb file");
  Scene scene;
  try {
    scene = loadGltfScene(path, options);
  } catch (const SceneError& e) {
    file.fail(e.what());
  }
  if (node.isObject()) {
    if (auto shutter = node.optional("shutter")) {
      if (hasCamera) shutter->fail("give the shutter in \"camera\" when the JSON scene has its own camera");
      parseShutter(*shutter, scene.camera);
    }
  }
  return scene;
}

// A light named like one already in the scene (from an include) replaces it.
void addLight(Scene& scene, PunctualLight light) {
  if (!light.name.empty()) {
    for (PunctualLight& existing : scene.punctualLights) {
      if (existing.name == light.name) {
        existing = std::move(light);
        return;
      }
    }
  }
  scene.punctualLights.push_back(std::move(light));
}

}  // namespace

Scene parseScene(std::string_view text, const std::filesystem::path& file) {
  const std::string label = file.string();
  const nlohmann::json document = parseJsonDocument(text, label);
  const JsonNode root(document, "", label);
  root.expectKeys({"include", "fps", "seed", "roughness_threshold", "render", "camera", "materials",
                   "environment", "lights", "shapes"});

  const std::filesystem::path folder = file.parent_path();
  const double fps = root.has("fps") ? root["fps"].number(1e-3, 1e6) : 24;
  const auto include = root.optional("include");
  Scene scene = include ? parseInclude(*include, folder, fps, root.has("camera")) : Scene{};
  scene.file = file;
  scene.fps = fps;
  if (auto seed = root.optional("seed")) scene.seed = static_cast<uint64_t>(seed->integer(0, 1 << 30));
  if (auto t = root.optional("roughness_threshold"))
    scene.roughnessThreshold = static_cast<float>(t->number(0, 4));
  if (auto render = root.optional("render")) parseRender(*render, scene.defaults);
  if (!include || root.has("camera")) parseCamera(root["camera"], scene.fps, scene.camera);

  // A material named like one of the included file's replaces it.
  std::map<std::string, int> materialIndex;
  for (size_t i = 0; i < scene.materialNames.size(); ++i) materialIndex[scene.materialNames[i]] = static_cast<int>(i);
  if (auto materials = include ? root.optional("materials") : std::optional<JsonNode>(root["materials"])) {
    for (const auto& [name, node] : materials->members()) {
      Material material = parseMaterial(node, folder, scene.textures);
      if (const auto it = materialIndex.find(name); it != materialIndex.end()) {
        // The BSDF is replaced; the included surface's cut-out and normal map stay.
        Material& replaced = scene.materials[static_cast<size_t>(it->second)];
        material.coverage = replaced.coverage;
        material.normalTexture = replaced.normalTexture;
        material.normalScale = replaced.normalScale;
        replaced = material;
        continue;
      }
      materialIndex[name] = static_cast<int>(scene.materials.size());
      scene.materialNames.push_back(name);
      scene.materials.push_back(material);
    }
  }
  if (auto env = root.optional("environment")) scene.environment = parseEnvironment(*env, folder);
  if (auto lights = root.optional("lights")) {
    for (const JsonNode& node : lights->elements()) addLight(scene, parsePunctualLight(node, scene.fps));
  }

  std::set<uint32_t> ids;
  for (const SceneObject& object : scene.objects) ids.insert(object.objectId);
  if (auto shapes = include ? root.optional("shapes") : std::optional<JsonNode>(root["shapes"])) {
    const auto elements = shapes->elements();
    const size_t first = scene.objects.size();
    for (size_t i = 0; i < elements.size(); ++i) {
      SceneObject object = parseShape(elements[i], first + i, scene, materialIndex, folder);
      if (!ids.insert(object.objectId).second)
        (elements[i].has("object_id") ? elements[i]["object_id"] : elements[i])
            .fail("object id " + std::to_string(object.objectId) + " is used twice");
      scene.objects.push_back(std::move(object));
    }
    if (scene.objects.empty()) shapes->fail("a scene needs at least one shape");
  }
  return scene;
}

Scene loadScene(const std::filesystem::path& file) {
  if (isGltfFile(file)) return loadGltfScene(file);
  std::ifstream in(file, std::ios::binary);
  if (!in) throw SceneError(file.string() + ": cannot open the scene file");
  noteSceneInput(file);
  std::ostringstream text;
  text << in.rdbuf();
  return parseScene(text.str(), file);
}

}  // namespace pathfarm
