#include "renderer/scene/gltf/gltf_deformation.h"

#include <cmath>
#include <map>

namespace pathfarm {
namespace {

// Accessor `index` as VEC3s, checked to hold one per vertex.
std::vector<Vec3f> perVertexVec3(const GltfDocument& document, int index, size_t vertexCount,
                                 const std::string& pointer) {
  const std::vector<float> values = document.readFloats(index, 3, pointer);
  if (values.size() != 3 * vertexCount)
    document.fail(pointer, "has " + std::to_string(values.size() / 3) + " elements for " +
                               std::to_string(vertexCount) + " positions");
  std::vector<Vec3f> result(vertexCount);
  for (size_t i = 0; i < vertexCount; ++i) result[i] = {values[3 * i], values[3 * i + 1], values[3 * i + 2]};
  return result;
}

int attributeOf(const std::map<std::string, int>& attributes, const std::string& name) {
  const auto it = attributes.find(name);
  return it == attributes.end() ? -1 : it->second;
}

std::vector<MorphTarget> readTargets(const GltfDocument& document, const tinygltf::Primitive& primitive,
                                     const TriangleMesh& mesh, const std::string& pointer) {
  std::vector<MorphTarget> targets;
  for (size_t t = 0; t < primitive.targets.size(); ++t) {
    const std::string base = pointer + "/targets/" + std::to_string(t) + "/";
    MorphTarget target;
    const auto& attributes = primitive.targets[t];
    const size_t n = mesh.positions.size();
    if (const int a = attributeOf(attributes, "POSITION"); a >= 0)
      target.positions = perVertexVec3(document, a, n, base + "POSITION");
    if (const int a = attributeOf(attributes, "NORMAL"); a >= 0 && !mesh.normals.empty())
      target.normals = perVertexVec3(document, a, n, base + "NORMAL");
    if (const int a = attributeOf(attributes, "TANGENT"); a >= 0 && !mesh.tangents.empty())
      target.tangents = perVertexVec3(document, a, n, base + "TANGENT");
    targets.push_back(std::move(target));
  }
  return targets;
}

MorphWeights readWeights(const GltfDocument& document, const GltfNodeAnimation& animation, int nodeIndex,
                         size_t targetCount) {
  const tinygltf::Model& model = document.model();
  const tinygltf::Node& node = model.nodes[static_cast<size_t>(nodeIndex)];
  const tinygltf::Mesh& mesh = model.meshes[static_cast<size_t>(node.mesh)];
  const bool fromNode = !node.weights.empty();
  const std::vector<double>& given = fromNode ? node.weights : mesh.weights;
  const std::string pointer =
      fromNode ? gltfPointer("nodes", nodeIndex) + "/weights" : gltfPointer("meshes", node.mesh) + "/weights";
  if (!given.empty() && given.size() != targetCount)
    document.fail(pointer, "has " + std::to_string(given.size()) + " weights for " + std::to_string(targetCount) +
                               " morph targets");
  MorphWeights weights;
  weights.rest.assign(targetCount, 0.0f);
  for (size_t i = 0; i < given.size(); ++i) weights.rest[i] = gltfFactor(document, pointer, given[i], -1e3, 1e3);
  if (const KeyTrack* track = animation.weightTrack(nodeIndex)) {
    if (track->width != targetCount)
      document.fail(gltfPointer("nodes", nodeIndex), "its weights animation has " + std::to_string(track->width) +
                                                         " weights per key for " + std::to_string(targetCount) +
                                                         " morph targets");
    weights.animated = *track;
  }
  return weights;
}

// Each vertex's joints and weights from every JOINTS_n/WEIGHTS_n set, zero weights
// dropped and the rest normalized to sum to 1.
void readInfluences(const GltfDocument& document, const tinygltf::Primitive& primitive, size_t vertexCount,
                    size_t jointCount, const std::string& pointer, Skin& skin) {
  std::vector<std::vector<float>> joints, weights;
  for (int set = 0;; ++set) {
    const std::string j = "JOINTS_" + std::to_string(set), w = "WEIGHTS_" + std::to_string(set);
    const int ja = attributeOf(primitive.attributes, j), wa = attributeOf(primitive.attributes, w);
    if (ja < 0 && wa < 0) break;
    if (ja < 0 || wa < 0)
      document.fail(pointer + "/attributes", "has " + (ja < 0 ? w : j) + " without " + (ja < 0 ? j : w));
    joints.push_back(document.readFloats(ja, 4, pointer + "/attributes/" + j));
    weights.push_back(document.readFloats(wa, 4, pointer + "/attributes/" + w));
    for (const auto* values : {&joints.back(), &weights.back()})
      if (values->size() != 4 * vertexCount)
        document.fail(pointer + "/attributes/" + (values == &joints.back() ? j : w),
                      "has " + std::to_string(values->size() / 4) + " elements for " + std::to_string(vertexCount) +
                          " positions");
  }
  if (joints.empty()) document.fail(pointer + "/attributes", "the node has a skin but the mesh has no JOINTS_0");
  skin.firstInfluence.push_back(0);
  for (size_t v = 0; v < vertexCount; ++v) {
    float sum = 0;
    const size_t first = skin.influences.size();
    for (size_t set = 0; set < joints.size(); ++set) {
      for (size_t k = 0; k < 4; ++k) {
        const float weight = weights[set][4 * v + k];
        if (weight == 0) continue;
        if (weight < 0)
          document.fail(pointer + "/attributes/WEIGHTS_" + std::to_string(set),
                        "vertex " + std::to_string(v) + " has a negative weight");
        const float joint = joints[set][4 * v + k];
        if (!(joint >= 0 && joint < static_cast<float>(jointCount)) || joint != std::floor(joint))
          document.fail(pointer + "/attributes/JOINTS_" + std::to_string(set),
                        "vertex " + std::to_string(v) + " names joint " + std::to_string(static_cast<long>(joint)) +
                            ", outside the skin's " + std::to_string(jointCount) + " joints");
        skin.influences.push_back({static_cast<uint32_t>(joint), weight});
        sum += weight;
      }
    }
    if (!(sum > 0))
      document.fail(pointer + "/attributes/WEIGHTS_0", "vertex " + std::to_string(v) + " has no joint weight");
    for (size_t i = first; i < skin.influences.size(); ++i) skin.influences[i].weight /= sum;
    skin.firstInfluence.push_back(static_cast<uint32_t>(skin.influences.size()));
  }
}

Skin readSkin(const GltfDocument& document, const GltfNodeAnimation& animation, int nodeIndex,
              const tinygltf::Primitive& primitive, size_t vertexCount, const std::string& primitivePointer) {
  const tinygltf::Model& model = document.model();
  const int skinIndex = model.nodes[static_cast<size_t>(nodeIndex)].skin;
  if (static_cast<size_t>(skinIndex) >= model.skins.size())
    document.fail(gltfPointer("nodes", nodeIndex) + "/skin", "skin " + std::to_string(skinIndex) + " does not exist");
  const tinygltf::Skin& source = model.skins[static_cast<size_t>(skinIndex)];
  const std::string pointer = gltfPointer("skins", skinIndex);
  if (source.joints.empty()) document.fail(pointer + "/joints", "a skin needs at least one joint");
  Skin skin;
  for (const int joint : source.joints) {
    if (joint < 0 || static_cast<size_t>(joint) >= model.nodes.size())
      document.fail(pointer + "/joints", "node " + std::to_string(joint) + " does not exist");
    skin.joints.push_back(animation.worldTransform(joint, true));
  }
  if (source.inverseBindMatrices >= 0) {
    const std::vector<float> m = document.readFloats(source.inverseBindMatrices, 16, pointer + "/inverseBindMatrices");
    if (m.size() != 16 * source.joints.size())
      document.fail(pointer + "/inverseBindMatrices", "has " + std::to_string(m.size() / 16) + " matrices for " +
                                                          std::to_string(source.joints.size()) + " joints");
    for (size_t j = 0; j < source.joints.size(); ++j) {
      const float* c = &m[16 * j];  // column-major
      const std::array<float, 12> rows{c[0], c[4], c[8], c[12], c[1], c[5], c[9], c[13], c[2], c[6], c[10], c[14]};
      const float det = c[0] * (c[5] * c[10] - c[9] * c[6]) - c[4] * (c[1] * c[10] - c[9] * c[2]) +
                        c[8] * (c[1] * c[6] - c[5] * c[2]);
      if (!(std::abs(det) > 1e-12f))
        document.fail(pointer + "/inverseBindMatrices", "matrix " + std::to_string(j) + " is singular");
      skin.inverseBind.push_back(Transform::fromMatrix(rows));
    }
  } else {
    skin.inverseBind.assign(source.joints.size(), Transform());
  }
  readInfluences(document, primitive, vertexCount, source.joints.size(), primitivePointer, skin);
  return skin;
}

}  // namespace

std::shared_ptr<const MeshDeformation> importDeformation(const GltfDocument& document,
                                                         const GltfNodeAnimation& animation, int nodeIndex,
                                                         int primitiveIndex, std::shared_ptr<const TriangleMesh> mesh) {
  const tinygltf::Model& model = document.model();
  const tinygltf::Node& node = model.nodes[static_cast<size_t>(nodeIndex)];
  const tinygltf::Primitive& primitive =
      model.meshes[static_cast<size_t>(node.mesh)].primitives[static_cast<size_t>(primitiveIndex)];
  if (node.skin < 0 && primitive.targets.empty()) return nullptr;
  const std::string pointer = gltfPointer("meshes", node.mesh) + "/primitives/" + std::to_string(primitiveIndex);
  std::vector<MorphTarget> targets = readTargets(document, primitive, *mesh, pointer);
  MorphWeights weights = readWeights(document, animation, nodeIndex, targets.size());
  std::optional<Skin> skin;
  if (node.skin >= 0) skin = readSkin(document, animation, nodeIndex, primitive, mesh->positions.size(), pointer);
  const AnimatedTrs placement = skin ? AnimatedTrs() : animation.worldTransform(nodeIndex, true);
  return std::make_shared<MeshDeformation>(std::move(mesh), std::move(targets), std::move(weights), std::move(skin),
                                           placement);
}

}  // namespace pathfarm
