#pragma once
// Double-precision vectors and 3x3 matrices for the solvers that need more than float
// (the specular manifold walk converges to 1e-6 on its constraints). Rendering itself
// stays in float (vecmath.h).
#include <cmath>

#include "renderer/math/vecmath.h"

namespace pathfarm {

struct Vec2d {
  double x = 0, y = 0;
};

struct Vec3d {
  double x = 0, y = 0, z = 0;

  constexpr Vec3d() = default;
  constexpr Vec3d(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
  constexpr explicit Vec3d(Vec3f v) : x(v.x), y(v.y), z(v.z) {}

  constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr Vec3d operator-() const { return {-x, -y, -z}; }
  Vec3f toFloat() const { return {static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)}; }
};

constexpr Vec3d operator+(Vec3d a, Vec3d b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
constexpr Vec3d operator-(Vec3d a, Vec3d b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
constexpr Vec3d operator*(Vec3d a, double s) { return {a.x * s, a.y * s, a.z * s}; }
constexpr Vec3d operator*(double s, Vec3d a) { return a * s; }
constexpr Vec3d operator/(Vec3d a, double s) { return {a.x / s, a.y / s, a.z / s}; }
constexpr double dot(Vec3d a, Vec3d b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3d cross(Vec3d a, Vec3d b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(Vec3d a) { return std::sqrt(dot(a, a)); }
inline Vec3d normalize(Vec3d a) { return a / length(a); }
inline bool isFinite(Vec3d a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }
inline double maxAbs(Vec3d a) { return std::max({std::abs(a.x), std::abs(a.y), std::abs(a.z)}); }
// The part of v orthogonal to the unit vector n.
constexpr Vec3d rejectFrom(Vec3d v, Vec3d n) { return v - n * dot(v, n); }

// Two unit tangents completing the unit normal n to a right-handed frame (Duff et al.
// 2017, as Frame::fromNormal does in float).
struct Tangents {
  Vec3d s, t;
};
inline Tangents tangentsOf(Vec3d n) {
  const double sign = std::copysign(1.0, n.z);
  const double a = -1.0 / (sign + n.z), b = n.x * n.y * a;
  return {{1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x}, {b, sign + n.y * n.y * a, -n.y}};
}

// A 3x3 matrix, row-major.
struct Mat3d {
  double m[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};

  static Mat3d identity() { return fromColumns({1, 0, 0}, {0, 1, 0}, {0, 0, 1}); }
  static Mat3d fromColumns(Vec3d a, Vec3d b, Vec3d c) {
    Mat3d r;
    for (int i = 0; i < 3; ++i) {
      r.m[i][0] = a[i];
      r.m[i][1] = b[i];
      r.m[i][2] = c[i];
    }
    return r;
  }
  Vec3d operator*(Vec3d v) const {
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
  }
  Mat3d operator*(const Mat3d& o) const {
    Mat3d r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) r.m[i][j] += m[i][k] * o.m[k][j];
    return r;
  }
  Mat3d operator+(const Mat3d& o) const {
    Mat3d r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r.m[i][j] = m[i][j] + o.m[i][j];
    return r;
  }
  Mat3d transposed() const {
    Mat3d r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r.m[i][j] = m[j][i];
    return r;
  }
  double determinant() const {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  }
  // The inverse by cofactors; the caller makes sure the matrix is regular.
  Mat3d inverse() const {
    const double s = 1.0 / determinant();
    Mat3d r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const int i1 = (j + 1) % 3, i2 = (j + 2) % 3, j1 = (i + 1) % 3, j2 = (i + 2) % 3;
        r.m[i][j] = (m[i1][j1] * m[i2][j2] - m[i1][j2] * m[i2][j1]) * s;
      }
    return r;
  }
};

}  // namespace pathfarm
