#include "renderer/scene/gltf/gltf_scene.h"

#include <cmath>
#include <map>

#include "renderer/scene/gltf/gltf_animation.h"
#include "renderer/scene/gltf/gltf_deformation.h"
#include "renderer/scene/gltf/gltf_lights.h"
#include "renderer/scene/gltf/gltf_materials.h"
#include "renderer/scene/gltf/gltf_mesh.h"

namespace pathfarm {
namespace {

constexpr double kRadiansToDegrees = 180.0 / 3.14159265358979323846;

// The root nodes of the scene to render.
std::vector<int> rootNodes(const GltfDocument& document, const GltfImportOptions& options) {
  const tinygltf::Model& model = document.model();
  if (model.scenes.empty()) {
    // No scene: every node without a parent is shown.
    std::vector<bool> child(model.nodes.size(), false);
    for (const tinygltf::Node& node : model.nodes)
      for (const int c : node.children)
        if (c >= 0 && static_cast<size_t>(c) < child.size()) child[static_cast<size_t>(c)] = true;
    std::vector<int> roots;
    for (size_t i = 0; i < child.size(); ++i)
      if (!child[i]) roots.push_back(static_cast<int>(i));
    return roots;
  }
  int chosen = model.defaultScene >= 0 ? model.defaultScene : 0;
  if (!options.sceneName.empty()) {
    chosen = -1;
    for (size_t i = 0; i < model.scenes.size(); ++i)
      if (model.scenes[i].name == options.sceneName) chosen = static_cast<int>(i);
    if (chosen < 0) document.fail("/scenes", "no scene is named \"" + options.sceneName + "\"");
  }
  if (static_cast<size_t>(chosen) >= model.scenes.size())
    document.fail("/scene", "scene " + std::to_string(chosen) + " does not exist");
  for (const int node : model.scenes[static_cast<size_t>(chosen)].nodes) {
    if (node < 0 || static_cast<size_t>(node) >= model.nodes.size())
      document.fail(gltfPointer("scenes", chosen) + "/nodes", "node " + std::to_string(node) + " does not exist");
  }
  return model.scenes[static_cast<size_t>(chosen)].nodes;
}

// Nodes in depth-first order from the roots (the hierarchy is known to be a forest).
std::vector<int> visibleNodes(const GltfDocument& document, const std::vector<int>& roots) {
  std::vector<int> order, stack(roots.rbegin(), roots.rend());
  while (!stack.empty()) {
    const int node = stack.back();
    stack.pop_back();
    order.push_back(node);
    const auto& children = document.model().nodes[static_cast<size_t>(node)].children;
    stack.insert(stack.end(), children.rbegin(), children.rend());
  }
  return order;
}

void importCamera(const GltfDocument& document, const GltfNodeAnimation& animation, const std::vector<int>& nodes,
                  const GltfImportOptions& options, Scene& scene) {
  const tinygltf::Model& model = document.model();
  for (const int n : nodes) {
    const tinygltf::Node& node = model.nodes[static_cast<size_t>(n)];
    if (node.camera < 0) continue;
    if (static_cast<size_t>(node.camera) >= model.cameras.size())
      document.fail(gltfPointer("nodes", n) + "/camera", "camera " + std::to_string(node.camera) + " does not exist");
    const tinygltf::Camera& camera = model.cameras[static_cast<size_t>(node.camera)];
    if (!options.cameraName.empty() && camera.name != options.cameraName && node.name != options.cameraName) continue;
    const std::string pointer = gltfPointer("cameras", node.camera);
    if (camera.type != "perspective")
      document.fail(pointer + "/type", "only perspective cameras are supported (this one is " + camera.type + ")");
    const double yfov = camera.perspective.yfov * kRadiansToDegrees;
    if (!(yfov > 0.01 && yfov < 179))
      document.fail(pointer + "/perspective/yfov", "the vertical field of view must lie in (0.01, 179) degrees");
    scene.camera.fovDegrees = static_cast<float>(yfov);
    // glTF cameras look along -z with +y up, as pathfarm's do; a camera is never scaled.
    scene.camera.transform = animation.worldTransform(n, false);
    const double aspect = camera.perspective.aspectRatio;
    if (aspect > 0 && std::isfinite(aspect)) {
      scene.defaults.height = 360;
      scene.defaults.width = std::max(1, static_cast<int>(std::lround(360 * std::min(aspect, 16.0))));
    }
    return;
  }
  if (!options.cameraName.empty())
    document.fail("/cameras", "no camera (or camera node) is named \"" + options.cameraName + "\"");
  if (options.requireCamera)
    document.fail("/cameras", "the scene has no camera; add one, or include the file from a JSON scene that "
                              "gives \"camera\"");
}

// Gives `object` its deformation. One that never changes is posed once into a static
// mesh, so the renderer treats it as any still object.
void placeDeformation(const GltfDocument& document, std::shared_ptr<const MeshDeformation> deformation,
                      SceneObject& object) {
  if (!deformation) return;
  object.transform = AnimatedTrs();  // poses are in world space
  if (!deformation->isAnimated()) {
    auto posed = std::make_shared<TriangleMesh>(deformation->rest());
    MeshDeformation::Pose pose = deformation->poseAt(0);
    posed->positions = std::move(pose.positions);
    posed->normals = std::move(pose.normals);
    posed->tangents = std::move(pose.tangents);
    object.mesh = std::move(posed);
    return;
  }
  if (object.isEmitter())
    document.fail("/materials", "object \"" + object.name + "\" emits light and deforms (skin or morph targets); "
                                "pathfarm samples only emitters of a fixed shape");
  object.deformation = std::move(deformation);
}

}  // namespace

bool isGltfFile(const std::filesystem::path& file) {
  const std::string ext = file.extension().string();
  return ext == ".gltf" || ext == ".glb";
}

Scene loadGltfScene(const std::filesystem::path& file, const GltfImportOptions& options) {
  return importGltfScene(GltfDocument(file), options);
}

Scene importGltfScene(const GltfDocument& document, const GltfImportOptions& options) {
  const tinygltf::Model& model = document.model();
  Scene scene;
  scene.file = document.file();
  scene.fps = options.fps;
  scene.defaults.width = 640;
  scene.defaults.height = 360;

  const GltfNodeAnimation animation(document);
  const std::vector<int> nodes = visibleNodes(document, rootNodes(document, options));
  GltfMaterials materials = importMaterials(document, scene);

  // Each (mesh, primitive, texture coordinates) becomes one shared TriangleMesh.
  std::map<std::tuple<int, int, TextureCoordinates>, std::shared_ptr<const TriangleMesh>> meshes;
  for (const int n : nodes) {
    const tinygltf::Node& node = model.nodes[static_cast<size_t>(n)];
    const std::string pointer = gltfPointer("nodes", n);
    if (node.mesh < 0) continue;
    if (static_cast<size_t>(node.mesh) >= model.meshes.size())
      document.fail(pointer + "/mesh", "mesh " + std::to_string(node.mesh) + " does not exist");
    const AnimatedTrs placement = animation.worldTransform(n, true);
    const auto& primitives = model.meshes[static_cast<size_t>(node.mesh)].primitives;
    for (size_t p = 0; p < primitives.size(); ++p) {
      const int material = primitives[p].material;
      if (material >= static_cast<int>(materials.sceneIndex.size()))
        document.fail(gltfPointer("meshes", node.mesh) + "/primitives/" + std::to_string(p) + "/material",
                      "material " + std::to_string(material) + " does not exist");
      const TextureCoordinates coordinates =
          material >= 0 ? materials.coordinates[static_cast<size_t>(material)] : TextureCoordinates{};
      auto& mesh = meshes[{node.mesh, static_cast<int>(p), coordinates}];
      if (!mesh) mesh = importPrimitive(document, node.mesh, static_cast<int>(p), coordinates);
      if (!mesh) continue;
      SceneObject object;
      object.name = node.name.empty() ? "node" + std::to_string(n) : node.name;
      if (primitives.size() > 1) object.name.append("#").append(std::to_string(p));
      object.objectId = static_cast<uint32_t>(scene.objects.size() + 1);
      object.type = ShapeType::Mesh;
      object.mesh = mesh;
      object.material = material >= 0 ? materials.sceneIndex[static_cast<size_t>(material)]
                                      : materials.defaultMaterial(scene);
      if (material >= 0) {
        object.emission = materials.emission[static_cast<size_t>(material)];
        object.emissionTexture = materials.emissionTexture[static_cast<size_t>(material)];
      }
      object.transform = placement;
      placeDeformation(document, importDeformation(document, animation, n, static_cast<int>(p), mesh), object);
      scene.objects.push_back(std::move(object));
    }
  }
  if (scene.objects.empty()) document.fail("", "the scene has no mesh with triangles to render");
  importCamera(document, animation, nodes, options, scene);
  importPunctualLights(document, animation, nodes, scene);
  if (animation.duration() > 0)
    scene.defaults.frameEnd = static_cast<int>(std::ceil(animation.duration() * options.fps - 1e-9));
  return scene;
}

}  // namespace pathfarm
