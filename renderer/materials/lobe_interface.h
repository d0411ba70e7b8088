#pragma once
// What every lobe implementation (conductor.h, dielectric.h, diffuse.h, plastic.h,
// metallic_roughness.h) returns to Bsdf (bsdf.h): which lobes it has, their values split
// by lobe, a sample, and the surface parameters it is built from.
#include "renderer/materials/material.h"

namespace pathfarm {

// Which lobes a BSDF has and how each counts in light-path expressions.
struct Lobe {
  LobeSymbol symbol;
  bool delta;  // a Dirac distribution: cannot be hit by next-event estimation
};

inline constexpr int kMaxLobes = 3;

struct LobeList {
  Lobe lobes[kMaxLobes];
  int count = 0;
};

// f(wo, wi) * |cos(wi)| of each lobe, index i for lobes().lobes[i]; entries past
// lobes().count and those of delta lobes are zero. sum() == eval(wo, wi) exactly (the
// same float additions eval performs, or additions of zero).
struct LobeValues {
  Rgb value[kMaxLobes];

  Rgb sum() const { return value[0] + value[1] + value[2]; }
};

struct BsdfSample {
  Vec3f wi;
  Rgb weight;        // f * |cos(wi)| / pdf, including the lobe selection probability
  float pdf = 0;     // solid-angle density; for a delta lobe, its selection probability
  LobeSymbol symbol = LobeSymbol::D;
  bool delta = false;
  // `weight` split by lobe (index as in lobes()). A delta sample puts all of `weight` on
  // the sampled lobe. A non-delta sample puts evalLobes(wo, wi).value[i] / pdf on lobe i,
  // with the same total density `pdf` for every lobe; only the rough plastic and the
  // metallic-roughness material have non-delta lobes that overlap, and there each part is
  // rounded on its own: the sum of lobeWeight equals `weight` to a relative 6 * 2^-24
  // (all parts are non-negative) rather than bit for bit, `weight` itself keeping the bits
  // it always had. Everywhere else one entry is `weight` and the others zero, so the sum is
  // exact.
  Rgb lobeWeight[kMaxLobes];
  // Index into lobes() of the lobe that sample() chose; with overlapping non-delta lobes,
  // lobeWeight may still give part of the weight to the other lobes.
  int lobe = 0;
};

// For the lobe implementations: a sample whose whole weight belongs to the lobe `lobe`.
inline BsdfSample oneLobeSample(Vec3f wi, Rgb weight, float pdf, LobeSymbol symbol, bool delta, int lobe) {
  BsdfSample s{wi, weight, pdf, symbol, delta, {}, lobe};
  s.lobeWeight[lobe] = weight;
  return s;
}

// What a BSDF needs that may vary over a surface, textures already looked up at the hit
// (surfaceAt in renderer/integrators/path_vertex.h). Code without a hit (the choice of
// decomposition, the specular chain search) uses the material's own values, `of`.
struct SurfaceParameters {
  Rgb albedo;       // diffuse reflectance; the base colour of MetallicRoughness
  float metallic;   // MetallicRoughness only, in [0, 1]
  float roughness;  // MetallicRoughness only: perceptual, GGX alpha = roughness^2
  float transmission;  // MetallicRoughness only, in [0, 1]

  static SurfaceParameters of(const Material& material, Rgb albedo) {
    return {albedo, material.metallic, material.roughness, material.transmission};
  }
};

}  // namespace pathfarm
