#pragma once
// The BSDF of a material at one surface point, in the local shading frame (z = shading
// normal, directions point away from the surface). Evaluation, sampling and density
// agree: for every non-delta lobe, sample() draws wi with density pdf(wo, wi) and
// returns weight = eval(wo, wi) / pdf(wo, wi).
#include <optional>

#include "renderer/materials/material.h"

namespace pathfarm {

// Which lobes a BSDF has and how each counts in light-path expressions.
struct Lobe {
  LobeSymbol symbol;
  bool delta;  // a Dirac distribution: cannot be hit by next-event estimation
};

struct LobeList {
  Lobe lobes[2];
  int count = 0;
};

struct BsdfSample {
  Vec3f wi;
  Rgb weight;        // f * |cos(wi)| / pdf, including the lobe selection probability
  float pdf = 0;     // solid-angle density; for a delta lobe, its selection probability
  LobeSymbol symbol = LobeSymbol::D;
  bool delta = false;
};

// Radiance travels from wi towards wo (the camera side); transmission includes the
// 1/eta^2 radiance scaling of the refracted direction.
class Bsdf {
 public:
  // `albedo` is the material's diffuse reflectance at this point (texture already looked up).
  Bsdf(const Material& material, Rgb albedo, float roughnessThreshold);

  // f(wo, wi) * |cos(wi)|; zero for pairs only delta lobes connect.
  Rgb eval(Vec3f wo, Vec3f wi) const;
  // Density of sample() over solid angle for the non-delta lobes.
  float pdf(Vec3f wo, Vec3f wi) const;
  std::optional<BsdfSample> sample(Vec3f wo, float uLobe, Vec2f u) const;

  // False when every lobe is a delta lobe, so next-event estimation is pointless.
  bool hasNonDeltaLobe() const;
  LobeList lobes() const;

 private:
  const Material& material_;
  Rgb albedo_;
  float roughnessThreshold_;
};

}  // namespace pathfarm
