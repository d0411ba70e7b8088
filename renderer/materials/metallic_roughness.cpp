#include "renderer/materials/metallic_roughness.h"

#include <algorithm>

#include "renderer/materials/fresnel.h"
#include "renderer/materials/specular_albedo.h"
#include "renderer/math/sampling.h"

namespace pathfarm {

namespace {

// Mirror image in the tangent plane: the other side of the thin sheet.
Vec3f mirrored(Vec3f v) { return {v.x, v.y, -v.z}; }

float mean(Rgb c) { return (c.r + c.g + c.b) * (1.0f / 3); }

}  // namespace

MetallicRoughnessBsdf::MetallicRoughnessBsdf(const Material& material, const SurfaceParameters& surface,
                                             float roughnessThreshold)
    : baseColor_(surface.albedo),
      metallic_(std::clamp(surface.metallic, 0.0f, 1.0f)),
      alpha_(std::clamp(surface.roughness, 0.0f, 1.0f) * std::clamp(surface.roughness, 0.0f, 1.0f)),
      // The albedo bound is tabulated up to kMaxSpecularAlbedoIor; every Fresnel term uses
      // the same clamped index, so the energy argument holds for any input.
      ior_(std::clamp(material.ior, 1.0f, kMaxSpecularAlbedoIor)),
      transmission_(std::clamp(surface.transmission, 0.0f, 1.0f)),
      distribution_(MicrofacetType::GGX, alpha_),
      delta_(alpha_ < kDeltaAlpha),
      reflectSymbol_(glossyLobeSymbol(alpha_, roughnessThreshold, LobeSymbol::R)),
      transmitSymbol_(glossyLobeSymbol(alpha_, roughnessThreshold, LobeSymbol::T)) {
  // Listed from the material, not the point, so that every point agrees (see the header).
  const bool dielectricAnywhere = material.metallic < 1 || material.metallicRoughnessTexture >= 0;
  int next = 1;
  diffuseLobe_ = dielectricAnywhere && (material.transmission < 1 || material.transmissionTexture >= 0) ? next++ : -1;
  transmissionLobe_ = dielectricAnywhere && material.transmission > 0 ? next++ : -1;
}

float MetallicRoughnessBsdf::dielectricFresnel(float cosThetaI) const {
  return fresnelDielectric(cosThetaI, ior_).reflectance;
}

Rgb MetallicRoughnessBsdf::reflectionFresnel(float cosThetaI) const {
  return fresnelSchlick(cosThetaI, baseColor_) * metallic_ + Rgb((1 - metallic_) * dielectricFresnel(cosThetaI));
}

float MetallicRoughnessBsdf::albedoBound(float cosTheta) const {
  return specularAlbedoBound(cosTheta, alpha_, ior_);
}

MetallicRoughnessBsdf::LobeProbabilities MetallicRoughnessBsdf::probabilities(Vec3f wo) const {
  const float dielectric = 1 - metallic_;
  const float reflection = mean(reflectionFresnel(wo.z));
  const float diffuse =
      diffuseLobe_ < 0 ? 0 : dielectric * (1 - transmission_) * mean(baseColor_) * (1 - albedoBound(wo.z));
  const float transmission =
      transmissionLobe_ < 0 ? 0 : dielectric * transmission_ * mean(baseColor_) * (1 - dielectricFresnel(wo.z));
  const float total = reflection + diffuse + transmission;
  if (!(total > 0)) return {};
  return {reflection / total, diffuse / total, transmission / total};
}

LobeValues MetallicRoughnessBsdf::evaluate(Vec3f wo, Vec3f wi) const {
  LobeValues v;
  if (wi.z > 0) {
    if (!delta_) {
      const Vec3f m = normalize(wo + wi);
      v.value[0] = reflectionFresnel(dot(wo, m)) * distribution_.reflectionEval(wo, wi, m);
    }
    const float weight = (1 - metallic_) * (1 - transmission_);
    if (diffuseLobe_ >= 0 && weight > 0) {
      // Kelemen and Szirmay-Kalos 2001: reflects rho (1 - E(cos_o)), what the coating leaves.
      const float base = (1 - albedoBound(wo.z)) * (1 - albedoBound(wi.z)) /
                         (kPi * (1 - averageSpecularAlbedoBound(alpha_, ior_)));
      v.value[diffuseLobe_] = baseColor_ * (weight * base * wi.z);
    }
  } else if (wi.z < 0 && transmissionLobe_ >= 0 && !delta_) {
    const Vec3f wiMirrored = mirrored(wi);
    const Vec3f m = normalize(wo + wiMirrored);
    const float weight = (1 - metallic_) * transmission_ * (1 - dielectricFresnel(dot(wo, m)));
    v.value[transmissionLobe_] = baseColor_ * (weight * distribution_.reflectionEval(wo, wiMirrored, m));
  }
  return v;
}

float MetallicRoughnessBsdf::density(Vec3f wo, Vec3f wi) const {
  const LobeProbabilities p = probabilities(wo);
  if (wi.z > 0) {
    float pdf = p.diffuse * cosineHemispherePdf(wi.z);
    if (!delta_) pdf += p.reflection * distribution_.reflectionPdf(wo, normalize(wo + wi));
    return pdf;
  }
  if (wi.z == 0 || delta_ || p.transmission == 0) return 0;
  return p.transmission * distribution_.reflectionPdf(wo, normalize(wo + mirrored(wi)));
}

LobeValues MetallicRoughnessBsdf::evalLobes(Vec3f wo, Vec3f wi) const {
  if (wo.z == 0) return {};
  return wo.z > 0 ? evaluate(wo, wi) : evaluate(mirrored(wo), mirrored(wi));
}

float MetallicRoughnessBsdf::pdf(Vec3f wo, Vec3f wi) const {
  if (wo.z == 0) return 0;
  return wo.z > 0 ? density(wo, wi) : density(mirrored(wo), mirrored(wi));
}

std::optional<BsdfSample> MetallicRoughnessBsdf::sample(Vec3f woIn, float uLobe, Vec2f u) const {
  if (woIn.z == 0) return std::nullopt;
  const bool flip = woIn.z < 0;
  const Vec3f wo = flip ? mirrored(woIn) : woIn;
  const auto result = [&](BsdfSample s) {
    if (flip) s.wi = mirrored(s.wi);
    return s;
  };
  const LobeProbabilities p = probabilities(wo);
  Vec3f wi;
  LobeSymbol symbol;
  int lobe;
  if (uLobe < p.reflection) {
    const Vec3f mirror{-wo.x, -wo.y, wo.z};
    if (delta_) {
      return result(
          oneLobeSample(mirror, reflectionFresnel(wo.z) / p.reflection, p.reflection, reflectSymbol_, true, 0));
    }
    const Vec3f m = distribution_.sampleNormal(wo, u);
    if (dot(wo, m) <= 0) return std::nullopt;
    wi = reflect(wo, m);
    if (wi.z <= 0) return std::nullopt;
    symbol = reflectSymbol_;
    lobe = 0;
  } else if (uLobe < p.reflection + p.diffuse || p.transmission == 0) {
    if (diffuseLobe_ < 0) return std::nullopt;  // only rounding of the probabilities gets here
    wi = sampleCosineHemisphere(u);
    if (wi.z <= 0) return std::nullopt;
    symbol = LobeSymbol::D;
    lobe = diffuseLobe_;
  } else {
    if (delta_) {
      const Rgb value = baseColor_ * ((1 - metallic_) * transmission_ * (1 - dielectricFresnel(wo.z)));
      return result(oneLobeSample(-wo, value / p.transmission, p.transmission, transmitSymbol_, true,
                                  transmissionLobe_));
    }
    const Vec3f m = distribution_.sampleNormal(wo, u);
    if (dot(wo, m) <= 0) return std::nullopt;
    const Vec3f reflected = reflect(wo, m);
    if (reflected.z <= 0) return std::nullopt;
    wi = mirrored(reflected);
    symbol = transmitSymbol_;
    lobe = transmissionLobe_;
  }
  // The non-delta lobes overlap (reflection and diffuse), so the weight is eval over the
  // mixture density, and each lobe's part is its own value over that density (bsdf.h).
  const float pdf = density(wo, wi);
  const LobeValues v = evaluate(wo, wi);
  BsdfSample s{wi, v.sum() / pdf, pdf, symbol, false, {}, lobe};
  for (int k = 0; k < kMaxLobes; ++k) s.lobeWeight[k] = v.value[k] / pdf;
  return result(s);
}

LobeList MetallicRoughnessBsdf::lobes() const {
  LobeList list{{{reflectSymbol_, delta_}}, 1};
  if (diffuseLobe_ >= 0) list.lobes[list.count++] = {LobeSymbol::D, false};
  if (transmissionLobe_ >= 0) list.lobes[list.count++] = {transmitSymbol_, delta_};
  return list;
}

}  // namespace pathfarm
