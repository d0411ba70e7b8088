#include "renderer/materials/bsdf.h"

#include "renderer/materials/conductor.h"
#include "renderer/materials/dielectric.h"
#include "renderer/materials/diffuse.h"
#include "renderer/materials/metallic_roughness.h"
#include "renderer/materials/plastic.h"

namespace pathfarm {

namespace {

// Builds the lobe implementation of the material on the stack and hands it to `f`. Each
// implementation offers eval, evalLobes, pdf, sample(wo, uLobe, u) and lobes() with the
// semantics of Bsdf. The switch compiles to direct calls: no
// virtual dispatch and no allocation per hit.
template <typename F>
auto visit(const Material& material, const SurfaceParameters& surface, float roughnessThreshold, F&& f) {
  const Rgb albedo = surface.albedo;
  switch (material.type) {
    case MaterialType::Conductor: return f(SmoothConductorBsdf(material));
    case MaterialType::RoughConductor: return f(RoughConductorBsdf(material, roughnessThreshold));
    case MaterialType::Dielectric: return f(SmoothDielectricBsdf(material.ior));
    case MaterialType::RoughDielectric: return f(RoughDielectricBsdf(material, roughnessThreshold));
    case MaterialType::Plastic: return f(SmoothPlasticBsdf(material, albedo));
    case MaterialType::RoughPlastic: return f(RoughPlasticBsdf(material, albedo, roughnessThreshold));
    case MaterialType::MetallicRoughness: return f(MetallicRoughnessBsdf(material, surface, roughnessThreshold));
    case MaterialType::Diffuse: break;
  }
  return f(DiffuseBsdf(albedo));
}

}  // namespace

Bsdf::Bsdf(const Material& material, const SurfaceParameters& surface, float roughnessThreshold)
    : material_(material), surface_(surface), roughnessThreshold_(roughnessThreshold) {}

Rgb Bsdf::eval(Vec3f wo, Vec3f wi) const {
  return visit(material_, surface_, roughnessThreshold_, [&](const auto& b) { return b.eval(wo, wi); });
}

LobeValues Bsdf::evalLobes(Vec3f wo, Vec3f wi) const {
  return visit(material_, surface_, roughnessThreshold_, [&](const auto& b) { return b.evalLobes(wo, wi); });
}

float Bsdf::pdf(Vec3f wo, Vec3f wi) const {
  return visit(material_, surface_, roughnessThreshold_, [&](const auto& b) { return b.pdf(wo, wi); });
}

std::optional<BsdfSample> Bsdf::sample(Vec3f wo, float uLobe, Vec2f u) const {
  const std::optional<BsdfSample> s =
      visit(material_, surface_, roughnessThreshold_, [&](const auto& b) { return b.sample(wo, uLobe, u); });
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
  return visit(material_, surface_, roughnessThreshold_, [](const auto& b) { return b.lobes(); });
}

}  // namespace pathfarm
