#pragma once
// Glass: Fresnel-weighted reflection and refraction, smooth (two delta lobes) or rough
// (Walter et al. 2007, with multiple-scattering compensation). wo may lie on either side:
// eta = ior when wo.z > 0 (entering), 1 / ior otherwise. Transmission carries the radiance
// scaling 1 / eta^2.
#include <optional>

#include "renderer/materials/lobe_interface.h"
#include "renderer/materials/microfacet.h"
#include "renderer/materials/multiple_scattering.h"

namespace pathfarm {

// wo mirrored above the surface, with the relative index seen from there (dielectric.cpp).
struct GlassOrientation;

class SmoothDielectricBsdf {
 public:
  explicit SmoothDielectricBsdf(float ior) : ior_(ior) {}

  Rgb eval(Vec3f, Vec3f) const { return {}; }
  LobeValues evalLobes(Vec3f, Vec3f) const { return {}; }
  float pdf(Vec3f, Vec3f) const { return 0; }
  // Chooses reflection with probability F, so the weight is 1 for reflection and
  // 1 / eta^2 for refraction.
  std::optional<BsdfSample> sample(Vec3f wo, float uLobe, Vec2f u) const;
  LobeList lobes() const { return {{{LobeSymbol::R, true}, {LobeSymbol::T, true}}, 2}; }

 private:
  float ior_;
};

// Walter et al.'s single scattering plus the light it loses between facets, returned by
// the compensation of multiple_scattering.h on both sides of the surface. Sampling picks
// that compensation with the share of the energy at wo it carries (the cosine hemisphere on
// either side), the facets otherwise.
class RoughDielectricBsdf {
 public:
  RoughDielectricBsdf(const Material& material, float roughnessThreshold);

  Rgb eval(Vec3f wo, Vec3f wi) const { return Rgb(evaluate(wo, wi).value); }
  // Reflection (index 0) when wi lies on wo's side of the surface, refraction (index 1)
  // otherwise: at any pair only one of them is nonzero.
  LobeValues evalLobes(Vec3f wo, Vec3f wi) const;
  float pdf(Vec3f wo, Vec3f wi) const { return evaluate(wo, wi).pdf; }
  // Walter et al. section 5.3 for single scattering: m from the distribution, then
  // reflection with probability F(wo.m), refraction otherwise.
  std::optional<BsdfSample> sample(Vec3f wo, float uLobe, Vec2f u) const;
  LobeList lobes() const { return {{{reflectSymbol_, false}, {transmitSymbol_, false}}, 2}; }

 private:
  // f * |cos(wi)| and the density of sample().
  struct Term {
    float value = 0, pdf = 0;
  };
  // These assume wo.z > 0, with eta = n(below) / n(above); `lobeProbability` is F(wo.m)
  // for reflection and 1 - F(wo.m) for refraction. One lobe through one facet.
  Term reflection(Vec3f wo, Vec3f wi, Vec3f m, float lobeProbability) const;
  Term transmission(Vec3f wo, Vec3f wi, Vec3f m, float lobeProbability, float eta) const;
  Term singleScattering(const GlassOrientation& o, Vec3f wi) const;
  // The probability of sampling the compensation for the oriented wo.
  float compensationShare(const GlassOrientation& o) const;
  // Single scattering and the compensation, their densities mixed as sample() mixes them.
  Term evaluate(const GlassOrientation& o, Vec3f wi) const;
  Term evaluate(Vec3f wo, Vec3f wi) const;

  float ior_;
  MicrofacetDistribution distribution_;
  DielectricMultipleScattering multiple_;
  LobeSymbol reflectSymbol_, transmitSymbol_;
};

}  // namespace pathfarm
