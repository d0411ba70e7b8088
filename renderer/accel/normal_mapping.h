#pragma once
// Normal maps (glTF normalTexture): the shading normal bent by a tangent-space normal
// read from a texture, in the OpenGL convention glTF uses (red = +tangent, green =
// +bitangent, the direction of increasing v in pathfarm's uv, i.e. up in the image).
// The tangent frame is the mesh's own (TANGENT, with the bitangent's handedness in
// TriangleMesh::tangentSigns) or, without one, that of the triangle's uv
// parameterization (dp/du, dp/dv), which is what tangent generators converge to on
// flat and gently curved surfaces but shows facets on coarse curved meshes.
#include "renderer/math/transform.h"
#include "renderer/scene/scene.h"

namespace pathfarm {

struct TriangleCorners {
  uint32_t i0, i1, i2;
  float u, v;  // barycentrics of corners 1 and 2
};

// The bent shading normal in world space; `shadingNormal` unchanged when the material
// has no normal map, the triangle's uvs are degenerate, or the bent normal would face
// away from it.
Vec3f normalMappedShadingNormal(const Scene& scene, const SceneObject& object, const TriangleMesh& mesh,
                                const TriangleCorners& corners, const Transform& toWorld, Vec3f shadingNormal,
                                Vec2f uv);

}  // namespace pathfarm
