#include "renderer/math/quaternion.h"

namespace pathfarm {

Quaternion Quaternion::fromAxisAngle(Vec3f axis, float radians) {
  const Vec3f a = normalize(axis);
  const float s = std::sin(0.5f * radians);
  return {std::cos(0.5f * radians), a.x * s, a.y * s, a.z * s};
}

Quaternion Quaternion::fromBasis(Vec3f x, Vec3f y, Vec3f z) {
  // Shepperd's method: pick the largest diagonal term for numerical stability.
  const float trace = x.x + y.y + z.z;
  Quaternion q;
  if (trace > 0) {
    const float s = 2 * std::sqrt(1 + trace);
    q = {0.25f * s, (y.z - z.y) / s, (z.x - x.z) / s, (x.y - y.x) / s};
  } else if (x.x > y.y && x.x > z.z) {
    const float s = 2 * std::sqrt(1 + x.x - y.y - z.z);
    q = {(y.z - z.y) / s, 0.25f * s, (y.x + x.y) / s, (z.x + x.z) / s};
  } else if (y.y > z.z) {
    const float s = 2 * std::sqrt(1 + y.y - x.x - z.z);
    q = {(z.x - x.z) / s, (y.x + x.y) / s, 0.25f * s, (z.y + y.z) / s};
  } else {
    const float s = 2 * std::sqrt(1 + z.z - x.x - y.y);
    q = {(x.y - y.x) / s, (z.x + x.z) / s, (z.y + y.z) / s, 0.25f * s};
  }
  return q.normalized();
}

Quaternion Quaternion::normalized() const {
  const float inv = 1.0f / std::sqrt(w * w + x * x + y * y + z * z);
  return {w * inv, x * inv, y * inv, z * inv};
}

Vec3f Quaternion::rotate(Vec3f v) const {
  // v' = v + 2 q_v x (q_v x v + w v)
  const Vec3f q{x, y, z};
  const Vec3f t = cross(q, v) * 2.0f;
  return v + t * w + cross(q, t);
}

float dot(const Quaternion& a, const Quaternion& b) {
  return a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z;
}

Quaternion operator*(const Quaternion& a, const Quaternion& b) {
  return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z,
          a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
          a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
          a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

Quaternion slerp(const Quaternion& a, const Quaternion& b0, float t) {
  Quaternion b = b0;
  float cosTheta = dot(a, b);
  if (cosTheta < 0) {
    b = {-b.w, -b.x, -b.y, -b.z};
    cosTheta = -cosTheta;
  }
  float wa, wb;
  if (cosTheta > 0.9995f) {  // nearly parallel: linear interpolation is exact enough and stable
    wa = 1 - t;
    wb = t;
  } else {
    const float theta = std::acos(cosTheta);
    const float sinTheta = std::sin(theta);
    wa = std::sin((1 - t) * theta) / sinTheta;
    wb = std::sin(t * theta) / sinTheta;
  }
  return Quaternion{wa * a.w + wb * b.w, wa * a.x + wb * b.x, wa * a.y + wb * b.y,
                    wa * a.z + wb * b.z}
      .normalized();
}

}  // namespace pathfarm
