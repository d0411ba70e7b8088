#pragma once
// Unit quaternions for rotations: built from an axis and angle, interpolated with slerp.
#include "renderer/math/vecmath.h"

namespace pathfarm {

struct Quaternion {
  float w = 1, x = 0, y = 0, z = 0;

  static Quaternion fromAxisAngle(Vec3f axis, float radians);
  // The rotation taking the x, y, z axes to the given orthonormal, right-handed basis.
  static Quaternion fromBasis(Vec3f x, Vec3f y, Vec3f z);
  Quaternion normalized() const;
  Vec3f rotate(Vec3f v) const;
};

float dot(const Quaternion& a, const Quaternion& b);
// Composition: (a * b).rotate(v) == a.rotate(b.rotate(v)).
Quaternion operator*(const Quaternion& a, const Quaternion& b);

// Spherical linear interpolation along the shorter arc.
Quaternion slerp(const Quaternion& a, const Quaternion& b, float t);

}  // namespace pathfarm
