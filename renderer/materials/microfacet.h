#pragma once
// Isotropic microfacet distributions (Walter et al. 2007, "Microfacet Models for
// Refraction through Rough Surfaces") in the local frame, z = macro normal.
//
// Sampling: GGX draws visible normals (Heitz 2018, "Sampling the GGX Distribution of
// Visible Normals"), density D_wo(m) = G1(wo, m) max(0, wo.m) D(m) / wo.z, which never
// proposes a facet wo cannot see and bounds a reflection's weight by F G1(wi) <= 1.
// Beckmann draws m with density D(m) cos(theta_m) (Walter et al. eq. 28), since its
// visible normals have no closed-form inverse. Callers use sampleNormal and normalPdf
// together and need not know which one is active.
#include "renderer/materials/material.h"
#include "renderer/math/vecmath.h"

namespace pathfarm {

class MicrofacetDistribution {
 public:
  MicrofacetDistribution(MicrofacetType type, float alpha);

  // Normal distribution D(m); zero for m below the macro surface.
  float D(Vec3f m) const;
  // Smith's monodirectional shadowing for v seen through a facet with normal m, zero
  // unless v lies on the same side of m as of the macro surface (Walter et al.'s chi+).
  float G1(Vec3f v, Vec3f m) const;
  // Separable approximation of the bidirectional shadowing-masking (Walter et al. eq. 23).
  float G(Vec3f wo, Vec3f wi, Vec3f m) const { return G1(wo, m) * G1(wi, m); }

  // A facet normal in the upper hemisphere for an outgoing direction with wo.z > 0.
  Vec3f sampleNormal(Vec3f wo, Vec2f u) const;
  // Density of sampleNormal over the solid angle of m.
  float normalPdf(Vec3f wo, Vec3f m) const;

  // Reflection through the facet m = half vector of (wo, wi), both above the surface:
  // f * cos(wi) without the Fresnel factor, D G / (4 wo.z) (Walter et al. eq. 20), and
  // the density of wi = reflect(wo, m) for m from sampleNormal, using the Jacobian
  // 1 / (4 |wo.m|) (eq. 14).
  float reflectionEval(Vec3f wo, Vec3f wi, Vec3f m) const { return D(m) * G(wo, wi, m) / (4 * wo.z); }
  float reflectionPdf(Vec3f wo, Vec3f m) const { return normalPdf(wo, m) / (4 * std::abs(dot(wo, m))); }

 private:
  MicrofacetType type_;
  float alpha_;
};

// A glossy lobe counts as its sharp symbol (R or T) only when smoother than the threshold.
inline LobeSymbol glossyLobeSymbol(float alpha, float roughnessThreshold, LobeSymbol sharpSymbol) {
  return alpha < roughnessThreshold ? sharpSymbol : LobeSymbol::D;
}

}  // namespace pathfarm
