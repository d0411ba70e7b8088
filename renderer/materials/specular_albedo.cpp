#include "renderer/materials/specular_albedo.h"

#include <algorithm>
#include <cmath>

#include "renderer/materials/specular_albedo_tabulation.h"
// kTabulatedAlbedo, kTabulatedAverage and their Excess counterparts, written at build time
// by tabulate_specular_albedo.cpp from specular_albedo::tabulate().
#include "specular_albedo_table.inc"

namespace pathfarm {
namespace {

using specular_albedo::kIor;
using specular_albedo::kMu;
using specular_albedo::kRoughness;
using specular_albedo::muNode;
static_assert(std::size(kTabulatedAlbedo) == size_t(kIor) * kRoughness * kMu);
static_assert(std::size(kTabulatedAverage) == size_t(kIor) * kRoughness);
static_assert(std::size(kTabulatedExcessAlbedo) == std::size(kTabulatedAlbedo));
static_assert(std::size(kTabulatedExcessAverage) == std::size(kTabulatedAverage));

// Cell index and weight of the upper node for x in [0, n - 1].
struct Cell {
  int index;
  float t;
};
Cell cell(float x, int n) {
  x = std::clamp(x, 0.0f, float(n - 1));
  const int index = std::min(int(x), n - 2);
  return {index, x - float(index)};
}

Cell roughnessCell(float alpha) { return cell(std::sqrt(std::max(0.0f, alpha)) * (kRoughness - 1), kRoughness); }
Cell iorCell(float eta) {
  return cell(std::cbrt(std::max(0.0f, (eta - 1) / (kMaxSpecularAlbedoIor - 1))) * (kIor - 1), kIor);
}

// Bilinear in roughness and ior over a quantity f(ior node, roughness node); the same
// weights for the albedo and its average keep the average exact for the interpolant.
template <typename F>
float interpolate(Cell r, Cell n, const F& f) {
  const auto along = [&](int k) { return (1 - r.t) * f(k, r.index) + r.t * f(k, r.index + 1); };
  return (1 - n.t) * along(n.index) + n.t * along(n.index + 1);
}

float lookUp(const float* albedo, float cosTheta, float alpha, float eta) {
  // Linear in cos(theta) between the nodes, as the average assumes; the node spacing is
  // what is quadratic.
  const float mu = std::clamp(cosTheta, 0.0f, 1.0f);
  const int i = cell(std::sqrt(mu) * (kMu - 1), kMu).index;
  const float a = muNode(i), b = muNode(i + 1);
  const float w = std::clamp((mu - a) / (b - a), 0.0f, 1.0f);
  return interpolate(roughnessCell(alpha), iorCell(eta), [&](int k, int j) {
    const float* row = &albedo[(size_t(k) * kRoughness + j) * kMu];
    return (1 - w) * row[i] + w * row[i + 1];
  });
}

float lookUpAverage(const float* average, float alpha, float eta) {
  return interpolate(roughnessCell(alpha), iorCell(eta),
                     [&](int k, int j) { return average[size_t(k) * kRoughness + j]; });
}

}  // namespace

float specularAlbedoBound(float cosTheta, float alpha, float eta) {
  return lookUp(kTabulatedAlbedo, cosTheta, alpha, eta);
}

float averageSpecularAlbedoBound(float alpha, float eta) { return lookUpAverage(kTabulatedAverage, alpha, eta); }

float specularExcessAlbedoBound(float cosTheta, float alpha, float eta) {
  return lookUp(kTabulatedExcessAlbedo, cosTheta, alpha, eta);
}

float averageSpecularExcessAlbedoBound(float alpha, float eta) {
  return lookUpAverage(kTabulatedExcessAverage, alpha, eta);
}

}  // namespace pathfarm
