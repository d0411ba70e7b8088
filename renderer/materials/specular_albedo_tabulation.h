#pragma once
// The nodes and the integration behind specular_albedo.h's table. The table is integrated
// once at build time (tabulate_specular_albedo.cpp writes it as source), not in every
// process that meets a metallic-roughness material: the integration takes about 0.35 s.
#include <algorithm>
#include <cmath>
#include <vector>

#include "renderer/materials/microfacet.h"
#include "renderer/materials/specular_albedo.h"

namespace pathfarm::specular_albedo {

// Nodes: cos(theta) = (i / (kMu - 1))^2, dense near grazing where Fresnel climbs to one;
// roughness sqrt(alpha) uniform; eta = 1 + (kMaxSpecularAlbedoIor - 1) (k / (kIor - 1))^3,
// dense near 1 where the Fresnel rise at grazing angles changes fastest with eta.
inline constexpr int kMu = 32, kRoughness = 24, kIor = 24;

constexpr float muNode(int i) {
  const float s = float(i) / (kMu - 1);
  return s * s;
}
constexpr float alphaNode(int j) {
  const float r = float(j) / (kRoughness - 1);
  return r * r;
}
constexpr float iorNode(int k) {
  const float s = float(k) / (kIor - 1);
  return 1 + (kMaxSpecularAlbedoIor - 1) * s * s * s;
}

// Where a value falls between the nodes: the lower node's index and the upper node's
// weight.
struct Cell {
  int index;
  float t;
};
// The cell of x in [0, n - 1] (clamped) among n nodes.
inline Cell cell(float x, int n) {
  x = std::clamp(x, 0.0f, float(n - 1));
  const int index = std::min(int(x), n - 2);
  return {index, x - float(index)};
}
inline Cell roughnessCell(float alpha) { return cell(std::sqrt(std::max(0.0f, alpha)) * (kRoughness - 1), kRoughness); }
// The cell of cos(theta) among the mu nodes, its weight linear in cos(theta) between them
// (as the tables' averages assume; the node spacing is what is quadratic).
inline Cell muCell(float cosTheta) {
  // A NaN cosine (a degenerate direction) reads the grazing node, not past the table.
  const float mu = cosTheta > 0.0f ? std::min(cosTheta, 1.0f) : 0.0f;
  const int i = cell(std::sqrt(mu) * (kMu - 1), kMu).index;
  const float a = muNode(i), b = muNode(i + 1);
  return {i, std::clamp((mu - a) / (b - a), 0.0f, 1.0f)};
}

inline Cell iorCell(float eta) {
  return cell(std::cbrt(std::max(0.0f, (eta - 1) / (kMaxSpecularAlbedoIor - 1))) * (kIor - 1), kIor);
}

// The interpolated value of a table laid out [ior][roughness][mu] (from `table`): linear in
// cos(theta), bilinear in roughness and ior. Its average (laid out [ior][roughness]) uses the
// same roughness and ior weights, which keeps the average exact for the interpolant.
template <typename Node>
float interpolateInRoughnessAndIor(float alpha, float eta, const Node& node) {
  const Cell r = roughnessCell(alpha), n = iorCell(eta);
  const auto along = [&](int k) { return (1 - r.t) * node(k, r.index) + r.t * node(k, r.index + 1); };
  return (1 - n.t) * along(n.index) + n.t * along(n.index + 1);
}
inline float tableAlbedo(const float* table, float cosTheta, float alpha, float eta) {
  const Cell m = muCell(cosTheta);
  return interpolateInRoughnessAndIor(alpha, eta, [&](int k, int j) {
    const float* row = &table[(size_t(k) * kRoughness + j) * kMu];
    return (1 - m.t) * row[m.index] + m.t * row[m.index + 1];
  });
}
inline float tableAverage(const float* average, float alpha, float eta) {
  return interpolateInRoughnessAndIor(alpha, eta, [&](int k, int j) { return average[size_t(k) * kRoughness + j]; });
}

struct Table {
  std::vector<float> albedo;   // [ior][roughness][mu], kIor * kRoughness * kMu nodes
  std::vector<float> average;  // [ior][roughness]
};

// What a table integrates: the dielectric Fresnel reflectance F, or its excess F - F(1)
// over normal incidence (specularExcessAlbedoBound).
enum class Reflectance { Fresnel, Excess };

// Integrates every node; deterministic, so the build's table and this agree bit for bit.
Table tabulate(Reflectance reflectance = Reflectance::Fresnel);

// The mean over a quadrature x quadrature midpoint grid of the normal sampler's unit square
// of weight(wo, m), for wo at cos(theta) = mu and m the sampled facet normal; samples with wo
// below the facet count as zero.
template <typename Weight>
double meanOverSampledNormals(const MicrofacetDistribution& distribution, float mu, int quadrature, Weight weight) {
  const Vec3f wo{std::sqrt(std::max(0.0f, 1 - mu * mu)), 0, mu};
  double sum = 0;
  for (int a = 0; a < quadrature; ++a) {
    for (int b = 0; b < quadrature; ++b) {
      const Vec2f u{(a + 0.5f) / quadrature, (b + 0.5f) / quadrature};
      const Vec3f m = distribution.sampleNormal(wo, u);
      if (dot(wo, m) > 0) sum += weight(wo, m);
    }
  }
  return sum / (double(quadrature) * quadrature);
}

// The same mean of weight(wo, m, wi) with wi the reflection of wo about m; samples with wi
// below the surface count as zero.
template <typename Weight>
double meanOverReflections(const MicrofacetDistribution& distribution, float mu, int quadrature, Weight weight) {
  return meanOverSampledNormals(distribution, mu, quadrature, [&](Vec3f wo, Vec3f m) {
    const Vec3f wi = reflect(wo, m);
    return wi.z > 0 ? double(weight(wo, m, wi)) : 0.0;
  });
}

// 2 integral L(mu) mu dmu over [0, 1] of the piecewise linear interpolant L of a row of
// kMu values on the mu nodes, exactly: the average that keeps a table's albedo identities
// exact for the interpolated values.
float cosineWeightedAverage(const float* row);

}  // namespace pathfarm::specular_albedo
