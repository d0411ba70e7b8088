#pragma once
// An orthonormal basis around a normal: BSDFs work in this local frame (z = normal).
#include "renderer/math/vecmath.h"

namespace pathfarm {

struct Frame {
  Vec3f s, t, n;

  // Duff et al. 2017, "Building an Orthonormal Basis, Revisited": branchless and
  // continuous except at n.z = -1 exactly.
  static Frame fromNormal(Vec3f normal) {
    const float sign = std::copysign(1.0f, normal.z);
    const float a = -1.0f / (sign + normal.z);
    const float b = normal.x * normal.y * a;
    return {{1.0f + sign * normal.x * normal.x * a, sign * b, -sign * normal.x},
            {b, sign + normal.y * normal.y * a, -normal.y},
            normal};
  }
  Vec3f toLocal(Vec3f v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
  Vec3f toWorld(Vec3f v) const { return s * v.x + t * v.y + n * v.z; }
};

}  // namespace pathfarm
