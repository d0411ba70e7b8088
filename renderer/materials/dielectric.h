#pragma once
// Glass: Fresnel-weighted reflection and refraction, smooth (two delta lobes) or rough
// (Walter et al. 2007). wo may lie on either side: eta = ior when wo.z > 0 (entering),
// 1 / ior otherwise. Transmission carries the radiance scaling 1 / eta^2.
#include <optional>

#include "renderer/materials/bsdf.h"
#include "renderer/materials/microfacet.h"

namespace pathfarm {

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

class RoughDielectricBsdf {
 public:
  RoughDielectricBsdf(const Material& material, float roughnessThreshold);

  Rgb eval(Vec3f wo, Vec3f wi) const { return Rgb(evaluate(wo, wi).value); }
  // Reflection (index 0) when wi lies on wo's side of the surface, refraction (index 1)
  // otherwise: at any pair only one of them is nonzero.
  LobeValues evalLobes(Vec3f wo, Vec3f wi) const;
  float pdf(Vec3f wo, Vec3f wi) const { return evaluate(wo, wi).pdf; }
  // Walter et al. section 5.3: m from the distribution, then reflection with probability
  // F(wo.m), refraction otherwise.
  std::optional<BsdfSample> sample(Vec3f wo, float uLobe, Vec2f u) const;
  LobeList lobes() const { return {{{reflectSymbol_, false}, {transmitSymbol_, false}}, 2}; }

 private:
  // f * |cos(wi)| and the density of sample(), of one lobe through one facet.
  struct Term {
    float value = 0, pdf = 0;
  };
  // Both assume wo.z > 0, with eta = n(below) / n(above); `lobeProbability` is F(wo.m)
  // for reflection and 1 - F(wo.m) for refraction.
  Term reflection(Vec3f wo, Vec3f wi, Vec3f m, float lobeProbability) const;
  Term transmission(Vec3f wo, Vec3f wi, Vec3f m, float lobeProbability, float eta) const;
  Term evaluate(Vec3f wo, Vec3f wi) const;

  float ior_;
  MicrofacetDistribution distribution_;
  LobeSymbol reflectSymbol_, transmitSymbol_;
};

}  // namespace pathfarm
