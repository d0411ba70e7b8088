#pragma once
// Warps from the unit square to directions and shapes, each with its density.
#include "renderer/math/vecmath.h"

namespace pathfarm {

// Concentric mapping of Shirley and Chiu 1997: low distortion, area preserving.
inline Vec2f sampleUniformDisk(Vec2f u) {
  const float ox = 2 * u.x - 1, oy = 2 * u.y - 1;
  if (ox == 0 && oy == 0) return {0, 0};
  float r, theta;
  if (std::abs(ox) > std::abs(oy)) {
    r = ox;
    theta = (kPi / 4) * (oy / ox);
  } else {
    r = oy;
    theta = (kPi / 2) - (kPi / 4) * (ox / oy);
  }
  return {r * std::cos(theta), r * std::sin(theta)};
}

inline Vec3f sampleCosineHemisphere(Vec2f u) {
  const Vec2f d = sampleUniformDisk(u);
  return {d.x, d.y, std::sqrt(std::max(0.0f, 1 - d.x * d.x - d.y * d.y))};
}
inline float cosineHemispherePdf(float cosTheta) { return cosTheta * kInvPi; }

inline Vec3f sampleUniformSphere(Vec2f u) {
  const float z = 1 - 2 * u.x;
  const float r = std::sqrt(std::max(0.0f, 1 - z * z));
  const float phi = 2 * kPi * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
}
inline constexpr float kUniformSpherePdf = 1.0f / (4 * kPi);

// Directions uniform inside the cone of half-angle acos(cosMax) around +z.
inline Vec3f sampleUniformCone(Vec2f u, float cosMax) {
  const float z = 1 - u.x * (1 - cosMax);
  const float r = std::sqrt(std::max(0.0f, 1 - z * z));
  const float phi = 2 * kPi * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
}
inline float uniformConePdf(float cosMax) { return 1 / (2 * kPi * (1 - cosMax)); }

// Barycentric coordinates (b1, b2) uniformly distributed over a triangle.
inline Vec2f sampleUniformTriangle(Vec2f u) {
  const float su = std::sqrt(u.x);
  return {1 - su, u.y * su};
}

inline float powerHeuristic(float pdfA, float pdfB) {
  const float a = pdfA * pdfA, b = pdfB * pdfB;
  return a / (a + b);
}

}  // namespace pathfarm
