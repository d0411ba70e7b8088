#pragma once
// Metals: a perfect mirror and a microfacet reflector, both weighted by conductor
// Fresnel (complex IOR per channel) or, with useSpecularColor, Schlick's approximation.
#include <optional>

#include "renderer/materials/lobe_interface.h"
#include "renderer/materials/microfacet.h"
#include "renderer/materials/multiple_scattering.h"

namespace pathfarm {

class SmoothConductorBsdf {
 public:
  explicit SmoothConductorBsdf(const Material& material) : material_(material) {}

  Rgb eval(Vec3f, Vec3f) const { return {}; }
  LobeValues evalLobes(Vec3f, Vec3f) const { return {}; }
  float pdf(Vec3f, Vec3f) const { return 0; }
  std::optional<BsdfSample> sample(Vec3f wo, float uLobe, Vec2f u) const;
  LobeList lobes() const { return {{{LobeSymbol::R, true}}, 1}; }

 private:
  const Material& material_;
};

// Cook-Torrance reflection in the form of Walter et al. 2007, eq. 20, plus the energy that
// single scattering loses (multiple_scattering.h), tinted by the Fresnel's average: a white
// conductor reflects all of a uniform sky at every roughness. Sampling picks the visible
// normals or, with the compensation's share of the energy at wo, the cosine hemisphere.
class RoughConductorBsdf {
 public:
  RoughConductorBsdf(const Material& material, float roughnessThreshold);

  Rgb eval(Vec3f wo, Vec3f wi) const;
  LobeValues evalLobes(Vec3f wo, Vec3f wi) const { return {{eval(wo, wi), Rgb()}}; }
  float pdf(Vec3f wo, Vec3f wi) const;
  std::optional<BsdfSample> sample(Vec3f wo, float uLobe, Vec2f u) const;
  LobeList lobes() const { return {{{symbol_, false}}, 1}; }

 private:
  // The probability of sampling the cosine hemisphere for wo (wo.z > 0).
  float compensationShare(float cosO) const;

  const Material& material_;
  MicrofacetDistribution distribution_;
  MultipleScattering multiple_;
  Rgb multipleTint_;  // F_ms
  LobeSymbol symbol_;
};

}  // namespace pathfarm
