#pragma once
// The BSDF of a material at one surface point, in the local shading frame (z = shading
// normal, directions point away from the surface). Evaluation, sampling and density
// agree: for every non-delta lobe, sample() draws wi with density pdf(wo, wi) and
// returns weight = eval(wo, wi) / pdf(wo, wi).
//
// Lobe split (for the path-space decomposition of Zimmer et al. 2015): evalLobes and
// BsdfSample::lobeWeight divide eval and weight among the lobes of lobes(), index i
// belonging to lobes().lobes[i], so that throughput can follow each lobe's symbol. The
// parts add up to the whole: bit for bit, except the rough plastic's sampled weight,
// whose coating and base parts are each divided by the pdf (see BsdfSample).
#include <optional>
#include <variant>

#include "renderer/materials/conductor.h"
#include "renderer/materials/dielectric.h"
#include "renderer/materials/diffuse.h"
#include "renderer/materials/lobe_interface.h"
#include "renderer/materials/metallic_roughness.h"
#include "renderer/materials/plastic.h"

namespace pathfarm {

// Radiance travels from wi towards wo (the camera side); transmission includes the
// 1/eta^2 radiance scaling of the refracted direction.
class Bsdf {
 public:
  Bsdf(const Material& material, const SurfaceParameters& surface, float roughnessThreshold);
  // `albedo` is the material's diffuse reflectance at this point (texture already looked
  // up); the other parameters are the material's own.
  Bsdf(const Material& material, Rgb albedo, float roughnessThreshold)
      : Bsdf(material, SurfaceParameters::of(material, albedo), roughnessThreshold) {}

  // f(wo, wi) * |cos(wi)|; zero for pairs only delta lobes connect.
  Rgb eval(Vec3f wo, Vec3f wi) const;
  // eval(wo, wi) split by lobe; see LobeValues. Dielectrics: the reflection lobe when wo
  // and wi lie on the same side of the surface, the transmission lobe otherwise.
  LobeValues evalLobes(Vec3f wo, Vec3f wi) const;
  // Density of sample() over solid angle for the non-delta lobes.
  float pdf(Vec3f wo, Vec3f wi) const;
  std::optional<BsdfSample> sample(Vec3f wo, float uLobe, Vec2f u) const;

  // False when every lobe is a delta lobe, so next-event estimation is pointless.
  bool hasNonDeltaLobe() const;
  LobeList lobes() const;

 private:
  // The material's lobes at this point, built once: the metallic-roughness lobes look up
  // their compensation tables and Fresnel averages when built, and a path vertex evaluates,
  // samples and asks the density several times.
  using Lobes = std::variant<DiffuseBsdf, SmoothConductorBsdf, RoughConductorBsdf, SmoothDielectricBsdf,
                             RoughDielectricBsdf, SmoothPlasticBsdf, RoughPlasticBsdf, MetallicRoughnessBsdf>;
  static Lobes lobesOf(const Material& material, const SurfaceParameters& surface, float roughnessThreshold);

  Lobes lobes_;
};

}  // namespace pathfarm
