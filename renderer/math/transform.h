#pragma once
// Affine transforms (3x4 row-major) with their inverse. Points, vectors and normals
// transform differently; each has its own method so the caller says which it holds.
#include <array>

#include "renderer/math/quaternion.h"
#include "renderer/math/vecmath.h"

namespace pathfarm {

// Translation, rotation and scale, composed as T * R * S.
struct Trs {
  Vec3f translation{0, 0, 0};
  Quaternion rotation{};
  Vec3f scale{1, 1, 1};
};

class Transform {
 public:
  Transform();  // identity
  static Transform fromTrs(const Trs& trs);
  // Camera-style frame: origin at `eye`, -z looking at `target`, y towards `up`.
  static Transform lookAt(Vec3f eye, Vec3f target, Vec3f up);
  // From a 3x4 row-major matrix; the inverse is computed.
  static Transform fromMatrix(const std::array<float, 12>& m);

  Vec3f point(Vec3f p) const { return apply(m_, p) + Vec3f{m_[3], m_[7], m_[11]}; }
  Vec3f vector(Vec3f v) const { return apply(m_, v); }
  // Normals transform by the inverse transpose.
  Vec3f normal(Vec3f n) const;
  Vec3f inversePoint(Vec3f p) const { return apply(inv_, p) + Vec3f{inv_[3], inv_[7], inv_[11]}; }
  Vec3f inverseVector(Vec3f v) const { return apply(inv_, v); }

  Transform operator*(const Transform& rhs) const;
  const std::array<float, 12>& matrix() const { return m_; }

 private:
  static Vec3f apply(const std::array<float, 12>& m, Vec3f v) {
    return {m[0] * v.x + m[1] * v.y + m[2] * v.z, m[4] * v.x + m[5] * v.y + m[6] * v.z,
            m[8] * v.x + m[9] * v.y + m[10] * v.z};
  }
  std::array<float, 12> m_;
  std::array<float, 12> inv_;
};

}  // namespace pathfarm
