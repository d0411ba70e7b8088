#pragma once
// An indexed triangle mesh in object space. Normals, uvs and tangents are per vertex and
// optional (empty when the source had none). A tangent's sign says the bitangent's
// handedness: bitangent = cross(normal, tangent) * sign.
#include <cstdint>
#include <vector>

#include "renderer/math/vecmath.h"

namespace pathfarm {

struct TriangleMesh {
  std::vector<Vec3f> positions;
  std::vector<Vec3f> normals;
  std::vector<Vec2f> uvs;
  std::vector<Vec3f> tangents;
  std::vector<float> tangentSigns;
  std::vector<uint32_t> indices;  // three per triangle

  size_t triangleCount() const { return indices.size() / 3; }
};

// Object-space primitives of the scene format.
TriangleMesh makeRectangle(float width, float height);  // in the xy plane, normal +z, centered
TriangleMesh makeBox(Vec3f size);                        // centered, outward normals

}  // namespace pathfarm
