#include "renderer/scene/mesh.h"

#include <cmath>

namespace pathfarm {

namespace {

// Appends one planar quad: corners center +/- uAxis +/- vAxis, where cross(uAxis, vAxis)
// points along `normal`. The quad spans uv (0,0) at center - uAxis - vAxis to (1,1) at
// center + uAxis + vAxis, and its two triangles are wound counter-clockwise seen from
// the side `normal` points to.
void appendQuad(TriangleMesh& mesh, Vec3f center, Vec3f uAxis, Vec3f vAxis, Vec3f normal) {
  const auto base = static_cast<uint32_t>(mesh.positions.size());
  mesh.positions.push_back(center - uAxis - vAxis);
  mesh.positions.push_back(center + uAxis - vAxis);
  mesh.positions.push_back(center + uAxis + vAxis);
  mesh.positions.push_back(center - uAxis + vAxis);
  for (int i = 0; i < 4; ++i) mesh.normals.push_back(normal);
  mesh.uvs.push_back({0, 0});
  mesh.uvs.push_back({1, 0});
  mesh.uvs.push_back({1, 1});
  mesh.uvs.push_back({0, 1});
  for (uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) mesh.indices.push_back(base + i);
}

Vec3f scaled(Vec3f a, Vec3f s) { return {a.x * s.x, a.y * s.y, a.z * s.z}; }

}  // namespace

TriangleMesh makeRectangle(float width, float height) {
  // Magnitudes only, so a negative extent cannot flip the winding against the normal.
  const float hw = std::abs(width) * 0.5f;
  const float hh = std::abs(height) * 0.5f;
  TriangleMesh mesh;
  mesh.positions.reserve(4);
  mesh.normals.reserve(4);
  mesh.uvs.reserve(4);
  mesh.indices.reserve(6);
  appendQuad(mesh, {0, 0, 0}, {hw, 0, 0}, {0, hh, 0}, {0, 0, 1});
  return mesh;
}

TriangleMesh makeBox(Vec3f size) {
  const Vec3f half{std::abs(size.x) * 0.5f, std::abs(size.y) * 0.5f, std::abs(size.z) * 0.5f};

  // Each face: outward normal, then the in-face axes chosen so that cross(u, v) equals
  // the normal and the texture reads upright when the face is seen from outside
  // (v up along +y on the side faces).
  struct Face {
    Vec3f normal, u, v;
  };
  static constexpr Face kFaces[6] = {
      {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}},   // +x
      {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},   // -x
      {{0, 1, 0}, {1, 0, 0}, {0, 0, -1}},   // +y
      {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},   // -y
      {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},    // +z
      {{0, 0, -1}, {-1, 0, 0}, {0, 1, 0}},  // -z
  };

  TriangleMesh mesh;
  mesh.positions.reserve(24);
  mesh.normals.reserve(24);
  mesh.uvs.reserve(24);
  mesh.indices.reserve(36);
  for (const Face& f : kFaces) {
    appendQuad(mesh, scaled(f.normal, half), scaled(f.u, half), scaled(f.v, half), f.normal);
  }
  return mesh;
}

}  // namespace pathfarm
