#pragma once
// Lambertian reflection.
#include <optional>

#include "renderer/materials/lobe_interface.h"

namespace pathfarm {

class DiffuseBsdf {
 public:
  explicit DiffuseBsdf(Rgb albedo) : albedo_(albedo) {}

  Rgb eval(Vec3f wo, Vec3f wi) const;
  LobeValues evalLobes(Vec3f wo, Vec3f wi) const { return {{eval(wo, wi), Rgb()}}; }
  float pdf(Vec3f wo, Vec3f wi) const;
  // Cosine-weighted hemisphere sampling: the weight is the albedo itself.
  std::optional<BsdfSample> sample(Vec3f wo, float uLobe, Vec2f u) const;
  LobeList lobes() const { return {{{LobeSymbol::D, false}}, 1}; }

 private:
  Rgb albedo_;
};

}  // namespace pathfarm
