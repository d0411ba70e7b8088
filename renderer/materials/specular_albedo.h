#pragma once
// The directional albedo of a rough dielectric's specular reflection, for energy-conserving
// layering (Kelemen and Szirmay-Kalos 2001, "A Microfacet Based Coupled Specular-Matte
// BRDF Model with Importance Sampling"): a base weighted by
//   (1 - E(wo)) (1 - E(wi)) / (pi (1 - E_avg))
// reflects exactly rho (1 - E(wo)) and is reciprocal, so coating + base never exceed one
// as long as E is at least the coating's true albedo.
//
// E here is the GGX reflection albedo E_s(mu, alpha, eta) = integral over the visible
// normals of F(wo.m) G1(wi, m) (the weight of the visible-normal sampler, microfacet.h),
// tabulated over cos(theta_o), perceptual roughness sqrt(alpha) and eta in [1, kMaxIor],
// each node raised by a margin that covers the quadrature and interpolation error, so that
// the interpolated E bounds E_s from above (metallic_roughness_test.cpp checks it
// against independent integration). E_avg is the cosine-weighted average of the same
// interpolant, computed exactly, so the base's albedo identity holds with the table's E.
namespace pathfarm {

inline constexpr float kMaxSpecularAlbedoIor = 3;

// E(mu) >= E_s(mu, alpha, eta), in [0, 1]; eta is clamped to [1, kMaxSpecularAlbedoIor].
float specularAlbedoBound(float cosTheta, float alpha, float eta);
// 2 * integral of E(mu) mu dmu over [0, 1], for the same alpha and eta.
float averageSpecularAlbedoBound(float alpha, float eta);

// The same bound (and average) for the albedo of F - F(1), the Fresnel reflectance above
// its value at normal incidence, tabulated alike: KHR_materials_specular scales that part
// apart from the rest (metallic_roughness.h).
float specularExcessAlbedoBound(float cosTheta, float alpha, float eta);
float averageSpecularExcessAlbedoBound(float alpha, float eta);

}  // namespace pathfarm
