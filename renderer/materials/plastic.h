#pragma once
// Plastic as in Mitsuba: a dielectric coating of index `ior` (smooth, or rough with a
// microfacet distribution) over a Lambertian base of albedo rho.
//
// Base: f * cos(wi) = rho (1 - F(wo.z)) (1 - F(wi.z)) cos(wi) / (pi eta^2 (1 - Fdr_int)),
// Mitsuba's default (linear) model: of the series of internal bounces between base and
// coating it keeps the Fresnel part, 1 / (1 - Fdr_int), but applies rho once, so colors
// are not darkened and saturated by rho^n (Mitsuba's "nonlinear" option). Since
// eta^2 (1 - Fdr_int) = 1 - Fdr_ext, the base reflects exactly rho (1 - F(wo.z)), and the
// smooth plastic's total albedo is F(wo.z) + rho (1 - F(wo.z)) <= 1.
//
// Sampling: the coating is chosen with probability
//   P = F(wo.z) / (F(wo.z) + (1 - F(wo.z)) mean(rho)),
// the share of the albedo each part contributes, the base (cosine-weighted) otherwise.
// The rough plastic uses the same P with the macro-normal Fresnel and returns the mixture
// weight f cos / (P pdf_coating + (1 - P) pdf_base), since both its lobes are non-delta.
#include <optional>

#include "renderer/materials/lobe_interface.h"
#include "renderer/materials/microfacet.h"

namespace pathfarm {

// What the smooth and rough plastics share: the coating's macro-normal Fresnel, the base
// lobe and the lobe selection.
class PlasticBase {
 public:
  PlasticBase(Rgb albedo, float ior);

  float fresnel(float cosTheta) const;
  // P above, for the outgoing direction.
  float coatingProbability(Vec3f wo) const;
  // The base's f * cos(wi) for wo.z, wi.z > 0.
  Rgb eval(Vec3f wo, Vec3f wi) const;

 private:
  Rgb albedo_;
  float ior_;
};

class SmoothPlasticBsdf {
 public:
  SmoothPlasticBsdf(const Material& material, Rgb albedo) : base_(albedo, material.ior) {}

  Rgb eval(Vec3f wo, Vec3f wi) const;
  // The delta coating (index 0) contributes nothing; everything is the base's (index 1).
  LobeValues evalLobes(Vec3f wo, Vec3f wi) const { return {{Rgb(), eval(wo, wi)}}; }
  float pdf(Vec3f wo, Vec3f wi) const;
  std::optional<BsdfSample> sample(Vec3f wo, float uLobe, Vec2f u) const;
  LobeList lobes() const { return {{{LobeSymbol::R, true}, {LobeSymbol::D, false}}, 2}; }

 private:
  PlasticBase base_;
};

class RoughPlasticBsdf {
 public:
  RoughPlasticBsdf(const Material& material, Rgb albedo, float roughnessThreshold);

  // The sum of evalLobes, coating + base: the same single addition it always was.
  Rgb eval(Vec3f wo, Vec3f wi) const;
  // Coating (index 0) and base (index 1).
  LobeValues evalLobes(Vec3f wo, Vec3f wi) const;
  float pdf(Vec3f wo, Vec3f wi) const;
  std::optional<BsdfSample> sample(Vec3f wo, float uLobe, Vec2f u) const;
  LobeList lobes() const { return {{{coatingSymbol_, false}, {LobeSymbol::D, false}}, 2}; }

 private:
  PlasticBase base_;
  MicrofacetDistribution distribution_;
  LobeSymbol coatingSymbol_;
};

}  // namespace pathfarm
