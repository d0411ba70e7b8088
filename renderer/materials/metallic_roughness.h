#pragma once
// glTF 2.0's pbrMetallicRoughness with KHR_materials_transmission, KHR_materials_ior and
// KHR_materials_specular (Material::type MetallicRoughness). At a point: base colour rho,
// metallic m, GGX alpha = roughness^2, transmission t, index eta. With half vector h,
//
//   f = m f_metal + (1 - m) f_dielectric
//   f_metal      = Schlick(wo.h; F0 = rho) D G / (4 cos_o cos_i)
//   f_dielectric = F'(wo.h) D G / (4 cos_o cos_i)                             specular
//                + (1 - t) rho (1 - E'(cos_o)) (1 - E'(cos_i)) / (pi (1 - E'_avg)) diffuse
//                + t rho (1 - F'(wo.h')) D G / (4 cos_o |cos_i|)              transmission
//                + t (F'_avg, or rho (1 - F'_avg) for wi below) f_ms         its compensation
//
// with D and G the GGX distribution and Smith shadowing of microfacet.h. F' is the exact
// dielectric Fresnel F of eta, F0 = F(1), remapped per channel as KHR_materials_specular
// asks, from s c0 at normal incidence to s at grazing (s its specularFactor, c0 =
// min(c F0, 1) with c its specularColorFactor): F' = A F + B with A = s (1 - c0) / (1 - F0)
// and B = s (c0 - F0) / (1 - F0). The extension blends the two ends with Schlick's weight,
// this with the exact Fresnel's; F' = F when s = c = 1, and F' >= 0 since F >= F0. E' bounds
// the albedo of F' with the bounds of specular_albedo.h: E' = min(A E + B, 1) with E the
// bound on the albedo of F when B >= 0 (c0 >= F0); otherwise, from F' = A (F - F0) + s c0,
// E' = min(A E_x + s c0, 1) with E_x the bound on the albedo of F - F0 (the constant
// s c0 reflects at most itself), which keeps the diffuse base as bright as it may be.
//
// Transmission is thin-walled, as glTF defines it without KHR_materials_volume: light
// passes the surface without refraction, through the reflection lobe mirrored in the
// tangent plane (wi' = (wi.x, wi.y, -wi.z), h' the half vector of wo and wi'), so a smooth
// surface transmits straight through (wi = -wo) and there is no 1 / eta^2. Nothing tracks
// an inside: the surface is two-sided, and wo below it mirrors both directions.
//
// Energy. Metal: Schlick <= 1, and what the Smith single-scattering lobe loses is given
// back by the compensation f_ms of multiple_scattering.h, tinted by Schlick's average
// (20 rho + 1) / 21: m F_ms f_ms joins f_metal in the reflection lobe, and a white metal
// reflects all of a uniform sky at every roughness. Dielectric, per channel, with E_s the
// albedo of the specular lobe (of F', bounded by E') and E that of the facets with Fresnel 1
// (multiple_scattering.h's table, which bounds it from above): the mirrored transmission
// leaves the facets along the reflected direction, so specular plus transmission reflect
// E_s + T = integral (F' + (1 - F')) G1(wi) D_wo(m) dm = E_true <= E, and the compensation
// f_ms (of the same table) returns 1 - E, split between the two sides by F'_avg (the
// average of F' for uniform light, as multiply scattered light is). The diffuse lobe
// reflects exactly rho (1 - E'(cos_o)) <= 1 - E_s since E' >= E_s. With rho <= 1 the
// dielectric part's albedo is at most E_s + t (E - E_s) + t (1 - E) + (1 - t) (1 - E_s) = 1,
// and so is the mix; a white sheet with t = 1 keeps all but the table's margin at every
// roughness. The bound's slack (0.006 to 0.015 away from grazing) costs the diffuse lobe
// about 1 % of rho. Every term is symmetric in wo and wi (wo.h = wi.h, and the mirrored transmission
// is symmetric in wo and wi'), so the BSDF is reciprocal.
//
// Delta lobes: when alpha < kDeltaAlpha the specular reflection is a mirror and the
// transmission passes straight through, each with its Fresnel weight at cos_o, like the
// smooth conductor and dielectric.
//
// Lobes: up to three at once (reflection R, diffuse D, transmission T), so LobeList holds
// three (lobe_interface.h): glTF materials with partial transmission need D and T together beside the
// specular R, and merging any two would give one lobe two symbols. A lobe is listed when
// the material can have it anywhere (reflection always; the diffuse base when the metallic
// factor or texture can leave a dielectric part and t < 1; the transmission when that part
// can exist and t > 0), so the list and its indices are the same at every point of a
// material and for material-level code; where a texel zeroes a lobe, its values are zero.
// Reflection and transmission count as R and T when alpha at the point is below the scene's
// threshold, D otherwise (glossyLobeSymbol). Code without a hit (auto decomposition, the
// specular chain search) decides from the roughness factor; a roughness texture only
// lowers roughness, so textured points may be R or T where the material-level decision
// said D: their paths then fall to the components the automaton has for them (often the
// residual), and the specular chain search ends at such an object as if it were diffuse.
//
// Sampling: a strategy with probability proportional to an estimate of its albedo at wo
// (macro-normal Fresnel for the specular and transmission parts, each compensation's colour
// times 1 - E, rho (1 - E') for the diffuse), then visible GGX normals (reflected, or
// reflected and mirrored) or the cosine hemisphere (mirrored for the transmission's
// compensation); the weight is eval over the mixture density of all non-delta strategies.
#include <optional>

#include "renderer/materials/lobe_interface.h"
#include "renderer/materials/microfacet.h"
#include "renderer/materials/multiple_scattering.h"

namespace pathfarm {

class MetallicRoughnessBsdf {
 public:
  // Below this GGX alpha the specular lobes are delta lobes (perceptual roughness ~0.03).
  static constexpr float kDeltaAlpha = 1e-3f;

  MetallicRoughnessBsdf(const Material& material, const SurfaceParameters& surface, float roughnessThreshold);

  // evalLobes(wo, wi).sum(): reflection + diffuse + transmission, as the lobes are listed.
  Rgb eval(Vec3f wo, Vec3f wi) const { return evalLobes(wo, wi).sum(); }
  LobeValues evalLobes(Vec3f wo, Vec3f wi) const;
  float pdf(Vec3f wo, Vec3f wi) const;
  std::optional<BsdfSample> sample(Vec3f wo, float uLobe, Vec2f u) const;
  LobeList lobes() const;

 private:
  // Sampling strategies: visible normals for the reflection, the cosine hemisphere for the
  // multiple-scattering compensation (part of the reflection lobe) and for the diffuse
  // base, mirrored visible normals for the transmission and the mirrored cosine hemisphere
  // for its compensation (part of the transmission lobe).
  struct LobeProbabilities {
    float reflection = 1, compensation = 0, diffuse = 0, transmission = 0, transmittedCompensation = 0;
  };
  // The methods below assume wo.z > 0 (mirrored by the public ones).
  LobeProbabilities probabilities(Vec3f wo) const;
  // m Schlick(rho) + (1 - m) F': the shared specular lobe's Fresnel.
  Rgb reflectionFresnel(float cosThetaI) const;
  Rgb dielectricFresnel(float cosThetaI) const;  // F'
  Rgb albedoBound(float cosTheta) const;         // E'
  Rgb averageAlbedoBound() const;                // E'_avg
  // E' from the bounds on the albedos of F and of F - F0 (the header).
  Rgb remappedAlbedo(float fresnelAlbedo, float excessAlbedo) const;
  // (1 - m) t (1 - F'(cos)) scale: the transmission lobe's weight.
  Rgb transmittance(float cosThetaI, float scale) const;
  LobeValues evaluate(Vec3f wo, Vec3f wi) const;
  float density(Vec3f wo, Vec3f wi) const;

  Rgb baseColor_;
  float metallic_, alpha_, ior_, transmission_;
  Rgb specularScale_, specularOffset_, normalReflectance_;  // A, B and s c0: F' = A F + B
  bool excessBound_;  // some channel has B < 0: E' reads the bound on F - F0
  MicrofacetDistribution distribution_;
  MultipleScattering multiple_;
  // The compensation lobe's colours (the header): m F_ms + (1 - m) t F'_avg reflected and
  // (1 - m) t rho (1 - F'_avg) transmitted.
  Rgb reflectionCompensation_, transmissionCompensation_;
  bool delta_;
  LobeSymbol reflectSymbol_, transmitSymbol_;
  int diffuseLobe_, transmissionLobe_;  // indices into lobes(), -1 when not listed
};

}  // namespace pathfarm
