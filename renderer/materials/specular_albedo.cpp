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
using specular_albedo::tableAlbedo;
using specular_albedo::tableAverage;
static_assert(std::size(kTabulatedAlbedo) == size_t(kIor) * kRoughness * kMu);
static_assert(std::size(kTabulatedAverage) == size_t(kIor) * kRoughness);
static_assert(std::size(kTabulatedExcessAlbedo) == std::size(kTabulatedAlbedo));
static_assert(std::size(kTabulatedExcessAverage) == std::size(kTabulatedAverage));

}  // namespace

float specularAlbedoBound(float cosTheta, float alpha, float eta) {
  return tableAlbedo(kTabulatedAlbedo, cosTheta, alpha, eta);
}

float averageSpecularAlbedoBound(float alpha, float eta) { return tableAverage(kTabulatedAverage, alpha, eta); }

float specularExcessAlbedoBound(float cosTheta, float alpha, float eta) {
  return tableAlbedo(kTabulatedExcessAlbedo, cosTheta, alpha, eta);
}

float averageSpecularExcessAlbedoBound(float alpha, float eta) {
  return tableAverage(kTabulatedExcessAverage, alpha, eta);
}

}  // namespace pathfarm
