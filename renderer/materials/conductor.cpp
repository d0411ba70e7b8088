#include "renderer/materials/conductor.h"

#include "renderer/materials/fresnel.h"

namespace pathfarm {

namespace {

Rgb conductorFresnel(const Material& material, float cosThetaI) {
  return material.useSpecularColor ? fresnelSchlick(cosThetaI, material.specularColor)
                                   : fresnelConductor(cosThetaI, material.eta, material.k);
}

}  // namespace

std::optional<BsdfSample> SmoothConductorBsdf::sample(Vec3f wo, float /*uLobe*/, Vec2f /*u*/) const {
  if (wo.z <= 0) return std::nullopt;
  return oneLobeSample({-wo.x, -wo.y, wo.z}, conductorFresnel(material_, wo.z), 1, LobeSymbol::R, true, 0);
}

RoughConductorBsdf::RoughConductorBsdf(const Material& material, float roughnessThreshold)
    : material_(material),
      distribution_(material.distribution, material.alpha),
      symbol_(glossyLobeSymbol(material.alpha, roughnessThreshold, LobeSymbol::R)) {}

Rgb RoughConductorBsdf::eval(Vec3f wo, Vec3f wi) const {
  if (wo.z <= 0 || wi.z <= 0) return {};
  const Vec3f m = normalize(wo + wi);
  return conductorFresnel(material_, dot(wo, m)) * distribution_.reflectionEval(wo, wi, m);
}

float RoughConductorBsdf::pdf(Vec3f wo, Vec3f wi) const {
  if (wo.z <= 0 || wi.z <= 0) return 0;
  return distribution_.reflectionPdf(wo, normalize(wo + wi));
}

std::optional<BsdfSample> RoughConductorBsdf::sample(Vec3f wo, float /*uLobe*/, Vec2f u) const {
  if (wo.z <= 0) return std::nullopt;
  const Vec3f m = distribution_.sampleNormal(wo, u);
  const float cosOM = dot(wo, m);
  if (cosOM <= 0) return std::nullopt;
  const Vec3f wi = reflect(wo, m);
  if (wi.z <= 0) return std::nullopt;
  const float pdf = distribution_.reflectionPdf(wo, m);
  const Rgb value = conductorFresnel(material_, cosOM) * distribution_.reflectionEval(wo, wi, m);
  return oneLobeSample(wi, value / pdf, pdf, symbol_, false, 0);
}

}  // namespace pathfarm
