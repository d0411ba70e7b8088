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

// F_avg of Schlick's approximation: F0 + (1 - F0) / 21.
Rgb schlickFresnelAverage(Rgb f0);
// F_avg of conductor Fresnel with complex index eta + i k, by quadrature (6 points).
Rgb conductorFresnelAverage(Rgb eta, Rgb k);

}  // namespace pathfarm
