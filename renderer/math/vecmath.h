#pragma once
// The small vector vocabulary every part of the renderer speaks: 2D and 3D float
// vectors for geometry, and Rgb for radiometric quantities, kept as distinct types
// so a color is never used as a direction.
#include <algorithm>
#include <cmath>

namespace pathfarm {

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 1.0f / kPi;

struct Vec2f {
  float x = 0, y = 0;
};

struct Vec3f {
  float x = 0, y = 0, z = 0;

  constexpr float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr Vec3f operator-() const { return {-x, -y, -z}; }
  constexpr Vec3f& operator+=(Vec3f o) { x += o.x; y += o.y; z += o.z; return *this; }
  constexpr Vec3f& operator-=(Vec3f o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
  constexpr Vec3f& operator*=(float s) { x *= s; y *= s; z *= s; return *this; }
};

constexpr Vec3f operator+(Vec3f a, Vec3f b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
constexpr Vec3f operator-(Vec3f a, Vec3f b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
constexpr Vec3f operator*(Vec3f a, float s) { return {a.x * s, a.y * s, a.z * s}; }
constexpr Vec3f operator*(float s, Vec3f a) { return a * s; }
constexpr Vec3f operator/(Vec3f a, float s) { return a * (1.0f / s); }
constexpr bool operator==(Vec3f a, Vec3f b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

constexpr float dot(Vec3f a, Vec3f b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3f cross(Vec3f a, Vec3f b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length(Vec3f a) { return std::sqrt(dot(a, a)); }
inline Vec3f normalize(Vec3f a) { return a / length(a); }
inline Vec3f lerp(Vec3f a, Vec3f b, float t) { return a * (1 - t) + b * t; }
inline Vec3f faceForward(Vec3f n, Vec3f v) { return dot(n, v) < 0 ? -n : n; }
inline Vec3f reflect(Vec3f wo, Vec3f n) { return -wo + n * (2 * dot(wo, n)); }
inline bool isFinite(Vec3f a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }
inline float maxComponent(Vec3f a) { return std::max({a.x, a.y, a.z}); }

struct Rgb {
  float r = 0, g = 0, b = 0;

  constexpr Rgb() = default;
  constexpr Rgb(float r_, float g_, float b_) : r(r_), g(g_), b(b_) {}
  constexpr explicit Rgb(float v) : r(v), g(v), b(v) {}

  constexpr float operator[](int i) const { return i == 0 ? r : (i == 1 ? g : b); }
  constexpr Rgb& operator+=(Rgb o) { r += o.r; g += o.g; b += o.b; return *this; }
  constexpr Rgb& operator*=(Rgb o) { r *= o.r; g *= o.g; b *= o.b; return *this; }
  constexpr Rgb& operator*=(float s) { r *= s; g *= s; b *= s; return *this; }
  constexpr bool isBlack() const { return r == 0 && g == 0 && b == 0; }
  constexpr float luminance() const { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }
  constexpr float maxComponent() const { return std::max({r, g, b}); }
  bool isFinite() const { return std::isfinite(r) && std::isfinite(g) && std::isfinite(b); }
};

constexpr Rgb operator+(Rgb a, Rgb b) { return {a.r + b.r, a.g + b.g, a.b + b.b}; }
constexpr Rgb operator-(Rgb a, Rgb b) { return {a.r - b.r, a.g - b.g, a.b - b.b}; }
constexpr Rgb operator*(Rgb a, Rgb b) { return {a.r * b.r, a.g * b.g, a.b * b.b}; }
constexpr Rgb operator*(Rgb a, float s) { return {a.r * s, a.g * s, a.b * s}; }
constexpr Rgb operator*(float s, Rgb a) { return a * s; }
constexpr Rgb operator/(Rgb a, float s) { return a * (1.0f / s); }
constexpr bool operator==(Rgb a, Rgb b) { return a.r == b.r && a.g == b.g && a.b == b.b; }

}  // namespace pathfarm
