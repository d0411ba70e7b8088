#pragma once
// Energy compensation for microfacet reflection (Kulla and Conty 2017, "Revisiting
// Physically Based Shading at Imageworks"). Single scattering with Smith shadowing drops
// the light that bounces between facets more than once: a white GGX metal of alpha 1
// reflects 0.31 of a uniform sky seen head-on. A second, diffuse-like lobe returns it:
//
//   f_ms(wo, wi) cos_i = F_ms (1 - E(cos_o)) (1 - E(cos_i)) cos_i / (pi (1 - E_avg))
//
// with E the albedo of the single-scattering lobe with Fresnel 1 (tabulated per
// distribution over cos(theta) and roughness at build time, linear in cos(theta) between
// the nodes), E_avg = 2 integral E(mu) mu dmu of that interpolant (exact), and
// F_ms = F_avg^2 E_avg / (1 - F_avg (1 - E_avg)) the colour of light that reflects
// several times, F_avg the cosine-weighted average of the Fresnel reflectance. With
// F = 1 the lobe reflects exactly 1 - E(cos_o), so single plus multiple scattering reflect
// E_true(cos_o) + 1 - E(cos_o): one, up to the table's error. f_ms is symmetric in wo and
// wi, so the sum stays reciprocal. It is sampled from the cosine hemisphere.
#include "renderer/materials/material.h"
#include "renderer/materials/microfacet_albedo_tabulation.h"
#include "renderer/math/vecmath.h"

namespace pathfarm {

class MultipleScattering {
 public:
  // alpha is clamped to the table's [0, 1].
  MultipleScattering(MicrofacetType type, float alpha);

  // E(cos(theta)): the single-scattering albedo with Fresnel 1.
  float albedo(float cosTheta) const;
  float averageAlbedo() const { return average_; }
  // f_ms cos_i without F_ms, for directions above the surface (zero otherwise).
  float eval(float cosO, float cosI) const;
  // The share of white light arriving along cos_o that single scattering loses and this
  // lobe returns: 1 - E(cos_o).
  float lost(float cosO) const { return 1 - albedo(cosO); }
  // F_ms for the Fresnel reflectance's cosine-weighted average, per channel.
  Rgb tint(Rgb fresnelAverage) const;

 private:
  int distribution_;
  float alpha_, average_;
};

// The same compensation for rough glass (dielectric.h), whose single scattering both reflects
// and refracts. E_s(mu) is the flux albedo of single scattering for light arriving from side
// s (outside, eta = ior; inside, eta = 1 / ior), tabulated over cos(theta), roughness and
// ior, and 1 - E_s(mu) what it loses. The lost light leaves on the same side with share
// r_s and on the other with t_s = 1 - r_s:
//
//   g_ss(wo, wi) cos_i = r_s (1 - E_s(cos_o)) (1 - E_s(cos_i)) cos_i / (pi (1 - E_s,avg))
//   g_st(wo, wi) cos_i = t_s (1 - E_s(cos_o)) (1 - E_t(cos_i)) cos_i / (pi (1 - E_t,avg))
//
// as flux (the BSDF divides refraction by eta^2), so light from side s keeps exactly
// E_s + 1 - E_s = 1 up to the table's error. Reciprocity across the interface,
// g_st(wo, wi) / n_t^2 = g_ts(wi, wo) / n_s^2, holds when t_in (1 - E_in,avg) = ior^2
// t_out (1 - E_out,avg): the flux that uniform light sends across the interface one way is
// the flux it sends back in equilibrium. t_in is the transmittance of a smooth interface to
// uniform light, 1 - F_avg(ior), lowered where that would make t_out exceed one.
class DielectricMultipleScattering {
 public:
  using Side = microfacet_albedo::Side;
  // alpha is clamped to [0, 1] and ior to [1, kMaxSpecularAlbedoIor].
  DielectricMultipleScattering(MicrofacetType type, float alpha, float ior);

  float albedo(Side side, float cosTheta) const;  // E_s
  float lost(Side side, float cosTheta) const { return 1 - albedo(side, cosTheta); }
  // g cos_i for wo on `side` (cosines positive, measured on each direction's own side):
  // toward wi on the same side, and toward wi on the other.
  float reflection(Side side, float cosO, float cosI) const;
  float transmission(Side side, float cosO, float cosI) const;
  // r_s: the share of the lost light that stays on side s.
  float reflectedShare(Side side) const { return 1 - transmitted_[int(side)]; }

 private:
  const float* albedoTable_[microfacet_albedo::kSides];
  float alpha_, ior_;
  float averageLost_[microfacet_albedo::kSides];  // 1 - E_s,avg
  float transmitted_[microfacet_albedo::kSides];  // t_s
};

// F_avg of Schlick's approximation: F0 + (1 - F0) / 21.
Rgb schlickFresnelAverage(Rgb f0);
// F_avg of conductor Fresnel with complex index eta + i k, by quadrature (6 points).
Rgb conductorFresnelAverage(Rgb eta, Rgb k);

}  // namespace pathfarm
