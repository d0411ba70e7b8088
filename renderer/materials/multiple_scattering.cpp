#include "renderer/materials/multiple_scattering.h"

#include <algorithm>
#include <cmath>

#include "renderer/materials/fresnel.h"
#include "renderer/materials/specular_albedo.h"
#include "renderer/materials/microfacet_albedo_tabulation.h"
#include "renderer/materials/specular_albedo_tabulation.h"
// kTabulatedMicrofacetAlbedo, kTabulatedMicrofacetAverage and their Dielectric counterparts,
// written at build time by tabulate_specular_albedo.cpp from microfacet_albedo::tabulate()
// and tabulateDielectric().
#include "specular_albedo_table.inc"

namespace pathfarm {
namespace {

using microfacet_albedo::kDistributions;
using specular_albedo::kMu;
using specular_albedo::kRoughness;
using specular_albedo::Cell;
using specular_albedo::muCell;
using specular_albedo::roughnessCell;
static_assert(std::size(kTabulatedMicrofacetAlbedo) == size_t(kDistributions) * kRoughness * kMu);
static_assert(std::size(kTabulatedMicrofacetAverage) == size_t(kDistributions) * kRoughness);
static_assert(std::size(kTabulatedDielectricAverage) ==
              size_t(kDistributions) * microfacet_albedo::kSides * specular_albedo::kIor * kRoughness);
static_assert(std::size(kTabulatedDielectricAlbedo) == std::size(kTabulatedDielectricAverage) * kMu);

// Below this 1 - E_avg the lobe has nothing to return (a mirror-like surface).
constexpr float kNothingLost = 1e-6f;

}  // namespace

MultipleScattering::MultipleScattering(MicrofacetType type, float alpha)
    : distribution_(microfacet_albedo::distributionIndex(type)), alpha_(std::clamp(alpha, 0.0f, 1.0f)) {
  const Cell r = roughnessCell(alpha_);
  const float* average = &kTabulatedMicrofacetAverage[size_t(distribution_) * kRoughness];
  average_ = (1 - r.t) * average[r.index] + r.t * average[r.index + 1];
}

float MultipleScattering::albedo(float cosTheta) const {
  // Linear in cos(theta) between the nodes, as the average assumes; bilinear with the
  // same roughness weights as the average.
  const Cell m = muCell(cosTheta), r = roughnessCell(alpha_);
  const auto at = [&](int j) {
    const float* row = &kTabulatedMicrofacetAlbedo[(size_t(distribution_) * kRoughness + j) * kMu];
    return (1 - m.t) * row[m.index] + m.t * row[m.index + 1];
  };
  return (1 - r.t) * at(r.index) + r.t * at(r.index + 1);
}

float MultipleScattering::eval(float cosO, float cosI) const {
  if (!(cosO > 0) || !(cosI > 0) || !(1 - average_ > kNothingLost)) return 0;  // NaN too
  return lost(cosO) * lost(cosI) * cosI / (kPi * (1 - average_));
}

Rgb MultipleScattering::tint(Rgb fresnelAverage) const {
  const auto channel = [&](int c) {
    const float f = std::clamp(fresnelAverage[c], 0.0f, 1.0f);
    return f * f * average_ / (1 - f * (1 - average_));
  };
  return {channel(0), channel(1), channel(2)};
}

DielectricMultipleScattering::DielectricMultipleScattering(MicrofacetType type, float alpha, float ior)
    : alpha_(std::clamp(alpha, 0.0f, 1.0f)), ior_(std::clamp(ior, 1.0f, kMaxSpecularAlbedoIor)) {
  for (const Side side : {Side::Entering, Side::Leaving}) {
    const size_t rows = microfacet_albedo::dielectricRows(type, side);
    albedoTable_[int(side)] = &kTabulatedDielectricAlbedo[rows * kMu];
    averageLost_[int(side)] = 1 - specular_albedo::tableAverage(&kTabulatedDielectricAverage[rows], alpha_, ior_);
  }
  const float in = averageLost_[int(Side::Entering)], out = averageLost_[int(Side::Leaving)];
  if (!(in > kNothingLost && out > kNothingLost)) {
    transmitted_[0] = transmitted_[1] = 0;
    return;
  }
  // t_in (1 - E_in,avg) = ior^2 t_out (1 - E_out,avg), with t_out <= 1.
  transmitted_[int(Side::Entering)] = std::min(1 - fresnelDiffuseReflectance(ior_), ior_ * ior_ * out / in);
  transmitted_[int(Side::Leaving)] = transmitted_[int(Side::Entering)] * in / (ior_ * ior_ * out);
}

float DielectricMultipleScattering::albedo(Side side, float cosTheta) const {
  return specular_albedo::tableAlbedo(albedoTable_[int(side)], cosTheta, alpha_, ior_);
}

float DielectricMultipleScattering::reflection(Side side, float cosO, float cosI) const {
  const float averageLost = averageLost_[int(side)];
  if (cosO <= 0 || cosI <= 0 || !(averageLost > kNothingLost)) return 0;
  return reflectedShare(side) * lost(side, cosO) * lost(side, cosI) * cosI / (kPi * averageLost);
}

float DielectricMultipleScattering::transmission(Side side, float cosO, float cosI) const {
  const Side other = side == Side::Entering ? Side::Leaving : Side::Entering;
  const float averageLost = averageLost_[int(other)];
  if (cosO <= 0 || cosI <= 0 || !(averageLost > kNothingLost)) return 0;
  return transmitted_[int(side)] * lost(side, cosO) * lost(other, cosI) * cosI / (kPi * averageLost);
}

Rgb schlickFresnelAverage(Rgb f0) { return f0 + (Rgb(1) - f0) * (1.0f / 21); }

Rgb conductorFresnelAverage(Rgb eta, Rgb k) {
  // 2 integral F(mu) mu dmu over [0, 1] by 6-point Gauss-Legendre: the integrand is smooth
  // in mu, and this runs for every rough conductor BSDF built.
  constexpr float kNodes[3] = {0.2386191861f, 0.6612093865f, 0.9324695142f};
  constexpr float kWeights[3] = {0.4679139346f, 0.3607615730f, 0.1713244924f};
  Rgb sum;
  for (int n = 0; n < 3; ++n) {
    for (const float side : {-1.0f, 1.0f}) {
      const float mu = 0.5f * (1 + side * kNodes[n]);
      sum += fresnelConductor(mu, eta, k) * (kWeights[n] * mu);  // weight w / 2 times 2 mu
    }
  }
  return sum;
}

}  // namespace pathfarm
