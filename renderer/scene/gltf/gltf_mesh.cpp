#include "renderer/scene/gltf/gltf_mesh.h"

#include <cmath>

namespace pathfarm {
namespace {

// The triangle list of a TRIANGLES, TRIANGLE_STRIP or TRIANGLE_FAN primitive.
std::vector<uint32_t> triangleList(const std::vector<uint32_t>& vertices, int mode) {
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    std::vector<uint32_t> list(vertices.begin(), vertices.end() - static_cast<long>(vertices.size() % 3));
    return list;
  }
  std::vector<uint32_t> list;
  for (size_t i = 2; i < vertices.size(); ++i) {
    if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
      list.insert(list.end(), {vertices[0], vertices[i - 1], vertices[i]});
    } else if (i % 2 == 0) {  // strips alternate winding to keep every triangle's facing
      list.insert(list.end(), {vertices[i - 2], vertices[i - 1], vertices[i]});
    } else {
      list.insert(list.end(), {vertices[i - 1], vertices[i - 2], vertices[i]});
    }
  }
  return list;
}

std::vector<Vec3f> vec3s(const std::vector<float>& values) {
  std::vector<Vec3f> result(values.size() / 3);
  for (size_t i = 0; i < result.size(); ++i) result[i] = {values[3 * i], values[3 * i + 1], values[3 * i + 2]};
  return result;
}

}  // namespace

std::shared_ptr<const TriangleMesh> importPrimitive(const GltfDocument& document, int meshIndex, int primitiveIndex,
                                                    const TextureCoordinates& coordinates) {
  const tinygltf::Primitive& primitive =
      document.model().meshes[static_cast<size_t>(meshIndex)].primitives[static_cast<size_t>(primitiveIndex)];
  const std::string pointer = gltfPointer("meshes", meshIndex) + "/primitives/" + std::to_string(primitiveIndex);
  const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
  if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
    document.warn(pointer + "/mode", "points and lines have no area and are not rendered");
    return nullptr;
  }
  const auto attribute = [&](const char* name) {
    const auto it = primitive.attributes.find(name);
    return it == primitive.attributes.end() ? -1 : it->second;
  };
  if (attribute("POSITION") < 0) document.fail(pointer + "/attributes", "has no POSITION attribute");

  auto mesh = std::make_shared<TriangleMesh>();
  mesh->positions = vec3s(document.readFloats(attribute("POSITION"), 3, pointer + "/attributes/POSITION"));
  const size_t vertexCount = mesh->positions.size();
  if (attribute("NORMAL") >= 0) {
    mesh->normals = vec3s(document.readFloats(attribute("NORMAL"), 3, pointer + "/attributes/NORMAL"));
    if (mesh->normals.size() != vertexCount)
      document.fail(pointer + "/attributes/NORMAL", "has " + std::to_string(mesh->normals.size()) +
                                                         " elements for " + std::to_string(vertexCount) + " positions");
  }
  const std::string uvName = "TEXCOORD_" + std::to_string(coordinates.set);
  if (attribute(uvName.c_str()) >= 0) {
    const std::vector<float> uv = document.readFloats(attribute(uvName.c_str()), 2, pointer + "/attributes/" + uvName);
    if (uv.size() != 2 * vertexCount)
      document.fail(pointer + "/attributes/" + uvName, "has " + std::to_string(uv.size() / 2) + " elements for " +
                                                           std::to_string(vertexCount) + " positions");
    mesh->uvs.resize(vertexCount);
    const auto& m = coordinates.m;
    for (size_t i = 0; i < vertexCount; ++i) {
      const float u = uv[2 * i], v = uv[2 * i + 1];
      mesh->uvs[i] = {m[0] * u + m[1] * v + m[2], 1 - (m[3] * u + m[4] * v + m[5])};
    }
  }

  if (attribute("TANGENT") >= 0 && !mesh->normals.empty()) {
    const std::vector<float> t = document.readFloats(attribute("TANGENT"), 4, pointer + "/attributes/TANGENT");
    if (t.size() != 4 * vertexCount)
      document.fail(pointer + "/attributes/TANGENT", "has " + std::to_string(t.size() / 4) + " elements for " +
                                                          std::to_string(vertexCount) + " positions");
    mesh->tangents.resize(vertexCount);
    mesh->tangentSigns.resize(vertexCount);
    for (size_t i = 0; i < vertexCount; ++i) {
      mesh->tangents[i] = {t[4 * i], t[4 * i + 1], t[4 * i + 2]};
      mesh->tangentSigns[i] = t[4 * i + 3] < 0 ? -1.0f : 1.0f;
    }
  }

  std::vector<uint32_t> vertices;
  if (primitive.indices >= 0) {
    vertices = document.readIndices(primitive.indices, vertexCount, pointer + "/indices");
  } else {
    vertices.resize(vertexCount);
    for (size_t i = 0; i < vertexCount; ++i) vertices[i] = static_cast<uint32_t>(i);
  }
  size_t degenerate = 0;
  const std::vector<uint32_t> list = triangleList(vertices, mode);
  for (size_t t = 0; t + 2 < list.size(); t += 3) {
    const uint32_t a = list[t], b = list[t + 1], c = list[t + 2];
    const Vec3f& pa = mesh->positions[a];
    if (length(cross(mesh->positions[b] - pa, mesh->positions[c] - pa)) == 0.0f) {
      ++degenerate;
      continue;
    }
    for (const uint32_t v : {a, b, c}) {
      if (!mesh->normals.empty() && !(length(mesh->normals[v]) > 1e-6f))
        document.fail(pointer + "/attributes/NORMAL", "the normal of vertex " + std::to_string(v) + " has zero length");
      if (!mesh->tangents.empty() && !(length(mesh->tangents[v]) > 1e-6f))
        document.fail(pointer + "/attributes/TANGENT", "the tangent of vertex " + std::to_string(v) + " has zero length");
    }
    mesh->indices.insert(mesh->indices.end(), {a, b, c});
  }
  for (std::vector<Vec3f>* directions : {&mesh->normals, &mesh->tangents}) {
    for (Vec3f& d : *directions) {
      const float l = length(d);
      if (l > 1e-6f && std::isfinite(l)) d = d / l;
    }
  }
  if (degenerate > 0)
    document.warn(pointer, std::to_string(degenerate) + " zero-area triangles dropped");
  if (mesh->indices.empty()) {
    document.warn(pointer, "has no triangle with area and is not rendered");
    return nullptr;
  }
  return mesh;
}

}  // namespace pathfarm
