#include "renderer/accel/normal_mapping.h"

#include <cmath>

namespace pathfarm {
namespace {

float determinant(const Transform& t) {
  const auto& m = t.matrix();
  return m[0] * (m[5] * m[10] - m[6] * m[9]) - m[1] * (m[4] * m[10] - m[6] * m[8]) +
         m[2] * (m[4] * m[9] - m[5] * m[8]);
}

// The world-space tangent and the bitangent's handedness at the hit; nothing when the
// frame is degenerate.
bool tangentFrame(const TriangleMesh& mesh, const TriangleCorners& c, const Transform& toWorld, Vec3f& tangent,
                  float& sign, Vec3f& uvBitangent) {
  const float w = 1 - c.u - c.v;
  if (!mesh.tangents.empty()) {
    tangent = toWorld.vector(mesh.tangents[c.i0] * w + mesh.tangents[c.i1] * c.u + mesh.tangents[c.i2] * c.v);
    // A mirroring placement flips the handedness (static meshes had theirs flipped when
    // they were placed in the world, where toWorld is the identity).
    sign = mesh.tangentSigns[c.i0] * (determinant(toWorld) < 0 ? -1.0f : 1.0f);
    uvBitangent = Vec3f{0, 0, 0};
    return dot(tangent, tangent) > 0;
  }
  if (mesh.uvs.empty()) return false;
  const Vec3f e1 = mesh.positions[c.i1] - mesh.positions[c.i0], e2 = mesh.positions[c.i2] - mesh.positions[c.i0];
  const Vec2f d1{mesh.uvs[c.i1].x - mesh.uvs[c.i0].x, mesh.uvs[c.i1].y - mesh.uvs[c.i0].y};
  const Vec2f d2{mesh.uvs[c.i2].x - mesh.uvs[c.i0].x, mesh.uvs[c.i2].y - mesh.uvs[c.i0].y};
  const float det = d1.x * d2.y - d1.y * d2.x;
  if (!(std::abs(det) > 1e-12f)) return false;
  tangent = toWorld.vector((e1 * d2.y - e2 * d1.y) / det);
  uvBitangent = toWorld.vector((e2 * d1.x - e1 * d2.x) / det);
  sign = 0;  // taken from dp/dv below
  return dot(tangent, tangent) > 0 && std::isfinite(dot(tangent, tangent));
}

}  // namespace

Vec3f normalMappedShadingNormal(const Scene& scene, const SceneObject& object, const TriangleMesh& mesh,
                                const TriangleCorners& corners, const Transform& toWorld, Vec3f shadingNormal,
                                Vec2f uv) {
  const Material& material = scene.materials[static_cast<size_t>(object.material)];
  if (material.normalTexture < 0) return shadingNormal;
  Vec3f tangent, uvBitangent;
  float sign = 0;
  if (!tangentFrame(mesh, corners, toWorld, tangent, sign, uvBitangent)) return shadingNormal;
  // Gram-Schmidt against the shading normal.
  tangent = tangent - shadingNormal * dot(shadingNormal, tangent);
  if (!(dot(tangent, tangent) > 1e-20f)) return shadingNormal;
  tangent = normalize(tangent);
  if (sign == 0) sign = dot(cross(shadingNormal, tangent), uvBitangent) < 0 ? -1.0f : 1.0f;
  const Vec3f bitangent = cross(shadingNormal, tangent) * sign;

  // Texels hold (n + 1) / 2; x and y are scaled by normalScale (glTF 2.0, 3.9.3).
  const Rgb texel = scene.textures[static_cast<size_t>(material.normalTexture)].lookup(uv);
  const float x = (2 * texel.r - 1) * material.normalScale, y = (2 * texel.g - 1) * material.normalScale;
  const float z = 2 * texel.b - 1;
  const Vec3f bent = tangent * x + bitangent * y + shadingNormal * z;
  const float length2 = dot(bent, bent);
  if (!(length2 > 1e-12f) || !std::isfinite(length2)) return shadingNormal;
  const Vec3f n = bent / std::sqrt(length2);
  return dot(n, shadingNormal) > 0 ? n : shadingNormal;
}

}  // namespace pathfarm
