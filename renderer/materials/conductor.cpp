#include "renderer/materials/conductor.h"

#include "renderer/materials/fresnel.h"
#include "renderer/math/sampling.h"

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
      multiple_(material.distribution, material.alpha),
      multipleTint_(multiple_.tint(material.useSpecularColor ? schlickFresnelAverage(material.specularColor)
                                                             : conductorFresnelAverage(material.eta, material.k))),
      symbol_(glossyLobeSymbol(material.alpha, roughnessThreshold, LobeSymbol::R)) {}

float RoughConductorBsdf::compensationShare(float cosO) const {
  const float single = multiple_.albedo(cosO);
  const float compensation = multiple_.lost(cosO) * (multipleTint_.r + multipleTint_.g + multipleTint_.b) / 3;
  return compensation > 0 ? compensation / (single + compensation) : 0;
}

Rgb RoughConductorBsdf::eval(Vec3f wo, Vec3f wi) const {
  if (wo.z <= 0 || wi.z <= 0) return {};
  const Vec3f m = normalize(wo + wi);
  return conductorFresnel(material_, dot(wo, m)) * distribution_.reflectionEval(wo, wi, m) +
         multipleTint_ * multiple_.eval(wo.z, wi.z);
}

float RoughConductorBsdf::pdf(Vec3f wo, Vec3f wi) const {
  if (wo.z <= 0 || wi.z <= 0) return 0;
  const float share = compensationShare(wo.z);
  return (1 - share) * distribution_.reflectionPdf(wo, normalize(wo + wi)) + share * cosineHemispherePdf(wi.z);
}

std::optional<BsdfSample> RoughConductorBsdf::sample(Vec3f wo, float uLobe, Vec2f u) const {
  if (wo.z <= 0) return std::nullopt;
  Vec3f wi;
  if (uLobe < compensationShare(wo.z)) {
    wi = sampleCosineHemisphere(u);
  } else {
    const Vec3f m = distribution_.sampleNormal(wo, u);
    if (dot(wo, m) <= 0) return std::nullopt;
    wi = reflect(wo, m);
  }
  if (wi.z <= 0) return std::nullopt;
  const float density = pdf(wo, wi);
  if (!(density > 0)) return std::nullopt;
  return oneLobeSample(wi, eval(wo, wi) / density, density, symbol_, false, 0);
}

}  // namespace pathfarm
