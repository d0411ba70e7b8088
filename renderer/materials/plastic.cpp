#include "renderer/materials/plastic.h"

#include "renderer/materials/fresnel.h"
#include "renderer/math/sampling.h"

namespace pathfarm {

PlasticBase::PlasticBase(Rgb albedo, float ior) : albedo_(albedo), ior_(ior) {}

float PlasticBase::fresnel(float cosTheta) const { return fresnelDielectric(cosTheta, ior_).reflectance; }

float PlasticBase::coatingProbability(Vec3f wo) const {
  const float f = fresnel(wo.z);
  const float total = f + (1 - f) * (albedo_.r + albedo_.g + albedo_.b) * (1.0f / 3);
  return total > 0 ? f / total : 1;
}

Rgb PlasticBase::eval(Vec3f wo, Vec3f wi) const {
  // Computed here rather than at construction: pdf, lobes and delta samples do not need it.
  const float scale = kInvPi / (ior_ * ior_ * (1 - fresnelDiffuseReflectance(1 / ior_)));
  return albedo_ * ((1 - fresnel(wo.z)) * (1 - fresnel(wi.z)) * wi.z * scale);
}

Rgb SmoothPlasticBsdf::eval(Vec3f wo, Vec3f wi) const {
  if (wo.z <= 0 || wi.z <= 0) return {};
  return base_.eval(wo, wi);
}

float SmoothPlasticBsdf::pdf(Vec3f wo, Vec3f wi) const {
  if (wo.z <= 0 || wi.z <= 0) return 0;
  return (1 - base_.coatingProbability(wo)) * cosineHemispherePdf(wi.z);
}

std::optional<BsdfSample> SmoothPlasticBsdf::sample(Vec3f wo, float uLobe, Vec2f u) const {
  if (wo.z <= 0) return std::nullopt;
  const float coating = base_.coatingProbability(wo);
  if (uLobe < coating) {
    return oneLobeSample({-wo.x, -wo.y, wo.z}, Rgb(base_.fresnel(wo.z) / coating), coating, LobeSymbol::R, true,
                         0);
  }
  const Vec3f wi = sampleCosineHemisphere(u);
  if (wi.z <= 0) return std::nullopt;
  const float pdf = (1 - coating) * cosineHemispherePdf(wi.z);
  return oneLobeSample(wi, base_.eval(wo, wi) / pdf, pdf, LobeSymbol::D, false, 1);
}

RoughPlasticBsdf::RoughPlasticBsdf(const Material& material, Rgb albedo, float roughnessThreshold)
    : base_(albedo, material.ior),
      distribution_(material.distribution, material.alpha),
      coatingSymbol_(glossyLobeSymbol(material.alpha, roughnessThreshold, LobeSymbol::R)) {}

LobeValues RoughPlasticBsdf::evalLobes(Vec3f wo, Vec3f wi) const {
  if (wo.z <= 0 || wi.z <= 0) return {};
  const Vec3f m = normalize(wo + wi);
  const float coating = base_.fresnel(dot(wo, m)) * distribution_.reflectionEval(wo, wi, m);
  return {{Rgb(coating), base_.eval(wo, wi)}};
}

Rgb RoughPlasticBsdf::eval(Vec3f wo, Vec3f wi) const {
  // Below the horizon both parts are +0 and so is their sum, as before.
  const LobeValues v = evalLobes(wo, wi);
  return v.value[0] + v.value[1];
}

float RoughPlasticBsdf::pdf(Vec3f wo, Vec3f wi) const {
  if (wo.z <= 0 || wi.z <= 0) return 0;
  const float coating = base_.coatingProbability(wo);
  return coating * distribution_.reflectionPdf(wo, normalize(wo + wi)) +
         (1 - coating) * cosineHemispherePdf(wi.z);
}

std::optional<BsdfSample> RoughPlasticBsdf::sample(Vec3f wo, float uLobe, Vec2f u) const {
  if (wo.z <= 0) return std::nullopt;
  Vec3f wi;
  LobeSymbol symbol;
  int lobe;
  if (uLobe < base_.coatingProbability(wo)) {
    const Vec3f m = distribution_.sampleNormal(wo, u);
    if (dot(wo, m) <= 0) return std::nullopt;
    wi = reflect(wo, m);
    symbol = coatingSymbol_;
    lobe = 0;
  } else {
    wi = sampleCosineHemisphere(u);
    symbol = LobeSymbol::D;
    lobe = 1;
  }
  if (wi.z <= 0) return std::nullopt;
  const float pdf = this->pdf(wo, wi);
  const LobeValues v = evalLobes(wo, wi);
  // The weight is eval(wo, wi) / pdf as it always was. Both lobes are non-delta, so each
  // gets its own f cos over the mixture density, whichever was sampled; the parts are
  // rounded separately, so their sum matches the weight only to rounding (see lobe_interface.h).
  return BsdfSample{wi, (v.value[0] + v.value[1]) / pdf, pdf, symbol, false,
                    {v.value[0] / pdf, v.value[1] / pdf}, lobe};
}

}  // namespace pathfarm
