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
using specular_albedo::Cell;
using specular_albedo::cell;
using specular_albedo::muCell;
using specular_albedo::roughnessCell;
static_assert(std::size(kTabulatedAlbedo) == size_t(kIor) * kRoughness * kMu);
static_assert(std::size(kTabulatedAverage) == size_t(kIor) * kRoughness);
static_assert(std::size(kTabulatedExcessAlbedo) == std::size(kTabulatedAlbedo));
static_assert(std::size(kTabulatedExcessAverage) == std::size(kTabulatedAverage));

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
  const Cell m = muCell(cosTheta);
  return interpolate(roughnessCell(alpha), iorCell(eta), [&](int k, int j) {
    const float* row = &albedo[(size_t(k) * kRoughness + j) * kMu];
    return (1 - m.t) * row[m.index] + m.t * row[m.index + 1];
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
