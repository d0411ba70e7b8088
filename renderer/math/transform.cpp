#include "renderer/math/transform.h"

namespace pathfarm {
namespace {

using Matrix = std::array<float, 12>;

constexpr Matrix kIdentity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};

Matrix multiply(const Matrix& a, const Matrix& b) {
  Matrix r{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 4; ++j) {
      float v = (j == 3) ? a[i * 4 + 3] : 0.0f;
      for (int k = 0; k < 3; ++k) v += a[i * 4 + k] * b[k * 4 + j];
      r[i * 4 + j] = v;
    }
  }
  return r;
}

// Inverse of an affine matrix, in double precision for accuracy.
Matrix invert(const Matrix& m) {
  const double a = m[0], b = m[1], c = m[2], d = m[4], e = m[5], f = m[6], g = m[8], h = m[9],
               i = m[10];
  const double det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
  const double s = 1.0 / det;
  const double r[9] = {(e * i - f * h) * s, (c * h - b * i) * s, (b * f - c * e) * s,
                       (f * g - d * i) * s, (a * i - c * g) * s, (c * d - a * f) * s,
                       (d * h - e * g) * s, (b * g - a * h) * s, (a * e - b * d) * s};
  Matrix inv{};
  for (int row = 0; row < 3; ++row) {
    double t = 0;
    for (int k = 0; k < 3; ++k) {
      inv[row * 4 + k] = static_cast<float>(r[row * 3 + k]);
      t -= r[row * 3 + k] * m[k * 4 + 3];
    }
    inv[row * 4 + 3] = static_cast<float>(t);
  }
  return inv;
}

}  // namespace

Transform::Transform() : m_(kIdentity), inv_(kIdentity) {}

Transform Transform::fromMatrix(const Matrix& m) {
  Transform t;
  t.m_ = m;
  t.inv_ = invert(m);
  return t;
}

Transform Transform::fromTrs(const Trs& trs) {
  // Columns of the rotation matrix are the rotated basis vectors, here from the unit
  // quaternion's closed form.
  const Quaternion& q = trs.rotation;
  const float xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z, xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z,
              wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
  const Vec3f rx{1 - 2 * (yy + zz), 2 * (xy + wz), 2 * (xz - wy)};
  const Vec3f ry{2 * (xy - wz), 1 - 2 * (xx + zz), 2 * (yz + wx)};
  const Vec3f rz{2 * (xz + wy), 2 * (yz - wx), 1 - 2 * (xx + yy)};
  const Vec3f s = trs.scale, t = trs.translation;
  Transform result;
  result.m_ = {rx.x * s.x, ry.x * s.y, rz.x * s.z, t.x,
               rx.y * s.x, ry.y * s.y, rz.y * s.z, t.y,
               rx.z * s.x, ry.z * s.y, rz.z * s.z, t.z};
  // (T R S)^-1 = S^-1 R^T T^-1: rows of R^T are R's columns, scaled by 1/s.
  const Vec3f inv{1 / s.x, 1 / s.y, 1 / s.z};
  const Vec3f r0 = rx * inv.x, r1 = ry * inv.y, r2 = rz * inv.z;
  result.inv_ = {r0.x, r0.y, r0.z, -dot(r0, t),
                 r1.x, r1.y, r1.z, -dot(r1, t),
                 r2.x, r2.y, r2.z, -dot(r2, t)};
  return result;
}

Transform Transform::lookAt(Vec3f eye, Vec3f target, Vec3f up) {
  const Vec3f back = normalize(eye - target);
  const Vec3f right = normalize(cross(up, back));
  const Vec3f trueUp = cross(back, right);
  return fromMatrix({right.x, trueUp.x, back.x, eye.x, right.y, trueUp.y, back.y, eye.y, right.z,
                     trueUp.z, back.z, eye.z});
}

Vec3f Transform::normal(Vec3f n) const {
  return {inv_[0] * n.x + inv_[4] * n.y + inv_[8] * n.z,
          inv_[1] * n.x + inv_[5] * n.y + inv_[9] * n.z,
          inv_[2] * n.x + inv_[6] * n.y + inv_[10] * n.z};
}

Transform Transform::operator*(const Transform& rhs) const {
  Transform r;
  r.m_ = multiply(m_, rhs.m_);
  r.inv_ = multiply(rhs.inv_, inv_);
  return r;
}

}  // namespace pathfarm
