#include "renderer/materials/bsdf.h"

namespace pathfarm {

Bsdf::Lobes Bsdf::lobesOf(const Material& material, const SurfaceParameters& surface, float roughnessThreshold) {
  const Rgb albedo = surface.albedo;
  switch (material.type) {
    case MaterialType::Conductor: return Lobes(std::in_place_type<SmoothConductorBsdf>, material);
    case MaterialType::RoughConductor:
      return Lobes(std::in_place_type<RoughConductorBsdf>, material, roughnessThreshold);
    case MaterialType::Dielectric: return Lobes(std::in_place_type<SmoothDielectricBsdf>, material.ior);
    case MaterialType::RoughDielectric:
      return Lobes(std::in_place_type<RoughDielectricBsdf>, material, roughnessThreshold);
    case MaterialType::Plastic: return Lobes(std::in_place_type<SmoothPlasticBsdf>, material, albedo);
    case MaterialType::RoughPlastic:
      return Lobes(std::in_place_type<RoughPlasticBsdf>, material, albedo, roughnessThreshold);
    case MaterialType::MetallicRoughness:
      return Lobes(std::in_place_type<MetallicRoughnessBsdf>, material, surface, roughnessThreshold);
    case MaterialType::Diffuse: break;
  }
  return Lobes(std::in_place_type<DiffuseBsdf>, albedo);
}

Bsdf::Bsdf(const Material& material, const SurfaceParameters& surface, float roughnessThreshold)
    : lobes_(lobesOf(material, surface, roughnessThreshold)) {}

Rgb Bsdf::eval(Vec3f wo, Vec3f wi) const {
  return std::visit([&](const auto& b) { return b.eval(wo, wi); }, lobes_);
}

LobeValues Bsdf::evalLobes(Vec3f wo, Vec3f wi) const {
  return std::visit([&](const auto& b) { return b.evalLobes(wo, wi); }, lobes_);
}

float Bsdf::pdf(Vec3f wo, Vec3f wi) const {
  return std::visit([&](const auto& b) { return b.pdf(wo, wi); }, lobes_);
}

std::optional<BsdfSample> Bsdf::sample(Vec3f wo, float uLobe, Vec2f u) const {
  const std::optional<BsdfSample> s = std::visit([&](const auto& b) { return b.sample(wo, uLobe, u); }, lobes_);
  // One net for every lobe: zero-density or non-finite samples (grazing facets, a
  // numerically degenerate refraction) end the path instead of poisoning the image.
  if (!s || !(s->pdf > 0) || !s->weight.isFinite() || !isFinite(s->wi)) return std::nullopt;
  return s;
}

bool Bsdf::hasNonDeltaLobe() const {
  // From the lobes, which know per point whether a glossy lobe has become a delta lobe.
  const LobeList list = lobes();
  for (int l = 0; l < list.count; ++l)
    if (!list.lobes[l].delta) return true;
  return false;
}

LobeList Bsdf::lobes() const {
  return std::visit([](const auto& b) { return b.lobes(); }, lobes_);
}

}  // namespace pathfarm
