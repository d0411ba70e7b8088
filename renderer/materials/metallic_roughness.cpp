#include "renderer/materials/metallic_roughness.h"

#include <algorithm>
#include <tuple>
#include <utility>

#include "renderer/materials/fresnel.h"
#include "renderer/materials/specular_albedo.h"
#include "renderer/math/sampling.h"

namespace pathfarm {

namespace {

// Mirror image in the tangent plane: the other side of the thin sheet.
Vec3f mirrored(Vec3f v) { return {v.x, v.y, -v.z}; }

float mean(Rgb c) { return (c.r + c.g + c.b) * (1.0f / 3); }

// The mean of a factor's channels, exactly the value of a grey one (as every factor is
// without KHR_materials_specular's colour).
float factorMean(Rgb c) { return c.r == c.g && c.g == c.b ? c.r : mean(c); }

Rgb perChannel(const auto& f) { return {f(0), f(1), f(2)}; }

// A, B and s c0 of F' = A F + B = A (F - F0) + s c0 (metallic_roughness.h), from
// KHR_materials_specular's factors.
std::tuple<Rgb, Rgb, Rgb> specularRemap(const Material& material, float ior) {
  const float s = std::clamp(material.specular, 0.0f, 1.0f);
  const float f0 = fresnelDielectric(1, ior).reflectance;
  const auto c0 = [&](int c) { return std::min(std::max(material.dielectricSpecularColor[c], 0.0f) * f0, 1.0f); };
  return {perChannel([&](int c) { return s * (1 - c0(c)) / (1 - f0); }),
          perChannel([&](int c) { return s * (c0(c) - f0) / (1 - f0); }), perChannel([&](int c) { return s * c0(c); })};
}

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
      multiple_(MicrofacetType::GGX, alpha_),
      reflectionCompensation_(multiple_.tint(schlickFresnelAverage(baseColor_)) * metallic_),
      delta_(alpha_ < kDeltaAlpha),
      reflectSymbol_(glossyLobeSymbol(alpha_, roughnessThreshold, LobeSymbol::R)),
      transmitSymbol_(glossyLobeSymbol(alpha_, roughnessThreshold, LobeSymbol::T)) {
  std::tie(specularScale_, specularOffset_, normalReflectance_) = specularRemap(material, ior_);
  excessBound_ = specularOffset_.r < 0 || specularOffset_.g < 0 || specularOffset_.b < 0;
  // What the transmitting part's facets lose leaves on either side: reflected with the
  // average of F', refracted (and tinted) with the rest. A BSDF is built at every hit, so
  // the average (logarithms) is computed only where something transmits.
  const float transmitting = (1 - metallic_) * transmission_;
  if (transmitting > 0 && !delta_) {
    const float fresnelAverage = fresnelDiffuseReflectance(ior_);
    const Rgb reflectedShare = perChannel(
        [&](int c) { return std::clamp(specularScale_[c] * fresnelAverage + specularOffset_[c], 0.0f, 1.0f); });
    reflectionCompensation_ += reflectedShare * transmitting;
    transmissionCompensation_ = baseColor_ * (Rgb(1) - reflectedShare) * transmitting;
  }
  // Listed from the material, not the point, so that every point agrees (see the header).
  const bool dielectricAnywhere = material.metallic < 1 || material.metallicRoughnessTexture >= 0;
  int next = 1;
  diffuseLobe_ = dielectricAnywhere && (material.transmission < 1 || material.transmissionTexture >= 0) ? next++ : -1;
  transmissionLobe_ = dielectricAnywhere && material.transmission > 0 ? next++ : -1;
}

Rgb MetallicRoughnessBsdf::dielectricFresnel(float cosThetaI) const {
  const float fresnel = fresnelDielectric(cosThetaI, ior_).reflectance;
  // F >= F0 holds up to rounding, which must not make F' negative.
  return perChannel([&](int c) { return std::max(specularScale_[c] * fresnel + specularOffset_[c], 0.0f); });
}

Rgb MetallicRoughnessBsdf::reflectionFresnel(float cosThetaI) const {
  return fresnelSchlick(cosThetaI, baseColor_) * metallic_ + dielectricFresnel(cosThetaI) * (1 - metallic_);
}

Rgb MetallicRoughnessBsdf::remappedAlbedo(float fresnelAlbedo, float excessAlbedo) const {
  return perChannel([&](int c) {
    const float bound = specularOffset_[c] >= 0 ? specularScale_[c] * fresnelAlbedo + specularOffset_[c]
                                                : specularScale_[c] * excessAlbedo + normalReflectance_[c];
    return std::min(bound, 1.0f);
  });
}

Rgb MetallicRoughnessBsdf::albedoBound(float cosTheta) const {
  return remappedAlbedo(specularAlbedoBound(cosTheta, alpha_, ior_),
                        excessBound_ ? specularExcessAlbedoBound(cosTheta, alpha_, ior_) : 0);
}

Rgb MetallicRoughnessBsdf::averageAlbedoBound() const {
  return remappedAlbedo(averageSpecularAlbedoBound(alpha_, ior_),
                        excessBound_ ? averageSpecularExcessAlbedoBound(alpha_, ior_) : 0);
}

MetallicRoughnessBsdf::LobeProbabilities MetallicRoughnessBsdf::probabilities(Vec3f wo) const {
  const float dielectric = 1 - metallic_;
  const float reflection = mean(reflectionFresnel(wo.z));
  const float lost = delta_ ? 0 : multiple_.lost(wo.z);
  const float compensation = mean(reflectionCompensation_) * lost;
  const float transmittedCompensation = transmissionLobe_ < 0 ? 0 : mean(transmissionCompensation_) * lost;
  const float diffuse =
      diffuseLobe_ < 0 ? 0 : dielectric * (1 - transmission_) * mean(baseColor_) * factorMean(Rgb(1) - albedoBound(wo.z));
  const float transmission = transmissionLobe_ < 0 ? 0
                                                   : dielectric * transmission_ * mean(baseColor_) *
                                                         factorMean(Rgb(1) - dielectricFresnel(wo.z));
  const float total = reflection + compensation + diffuse + transmission + transmittedCompensation;
  if (!(total > 0)) return {};
  return {reflection / total, compensation / total, diffuse / total, transmission / total,
          transmittedCompensation / total};
}

Rgb MetallicRoughnessBsdf::transmittance(float cosThetaI, float scale) const {
  const Rgb fresnel = dielectricFresnel(cosThetaI);
  return perChannel([&](int c) { return (1 - metallic_) * transmission_ * (1 - fresnel[c]) * scale; });
}

LobeValues MetallicRoughnessBsdf::evaluate(Vec3f wo, Vec3f wi) const {
  LobeValues v;
  if (wi.z > 0) {
    if (!delta_) {
      const Vec3f m = normalize(wo + wi);
      v.value[0] = reflectionFresnel(dot(wo, m)) * distribution_.reflectionEval(wo, wi, m) +
                   reflectionCompensation_ * multiple_.eval(wo.z, wi.z);
    }
    const float weight = (1 - metallic_) * (1 - transmission_);
    if (diffuseLobe_ >= 0 && weight > 0) {
      // Kelemen and Szirmay-Kalos 2001: reflects rho (1 - E'(cos_o)), what the coating leaves.
      const Rgb outgoing = albedoBound(wo.z), incoming = albedoBound(wi.z), average = averageAlbedoBound();
      v.value[diffuseLobe_] = baseColor_ * perChannel([&](int c) {
        if (!(average[c] < 1)) return 0.0f;  // a coating that reflects everything
        const float base = (1 - outgoing[c]) * (1 - incoming[c]) / (kPi * (1 - average[c]));
        return weight * base * wi.z;
      });
    }
  } else if (wi.z < 0 && transmissionLobe_ >= 0 && !delta_) {
    const Vec3f wiMirrored = mirrored(wi);
    const Vec3f m = normalize(wo + wiMirrored);
    const float eval = distribution_.reflectionEval(wo, wiMirrored, m);
    v.value[transmissionLobe_] = baseColor_ * transmittance(dot(wo, m), eval) +
                                 transmissionCompensation_ * multiple_.eval(wo.z, wiMirrored.z);
  }
  return v;
}

float MetallicRoughnessBsdf::density(Vec3f wo, Vec3f wi) const {
  const LobeProbabilities p = probabilities(wo);
  if (wi.z > 0) {
    float pdf = (p.compensation + p.diffuse) * cosineHemispherePdf(wi.z);
    if (!delta_) pdf += p.reflection * distribution_.reflectionPdf(wo, normalize(wo + wi));
    return pdf;
  }
  if (wi.z == 0 || delta_) return 0;
  const Vec3f wiMirrored = mirrored(wi);
  float pdf = p.transmittedCompensation * cosineHemispherePdf(wiMirrored.z);
  if (p.transmission > 0) pdf += p.transmission * distribution_.reflectionPdf(wo, normalize(wo + wiMirrored));
  return pdf;
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
  } else if (uLobe < p.reflection + p.compensation) {
    wi = sampleCosineHemisphere(u);
    if (wi.z <= 0) return std::nullopt;
    symbol = reflectSymbol_;
    lobe = 0;
  } else if (uLobe < p.reflection + p.compensation + p.diffuse ||
             p.transmission + p.transmittedCompensation == 0) {
    if (diffuseLobe_ < 0) return std::nullopt;  // only rounding of the probabilities gets here
    wi = sampleCosineHemisphere(u);
    if (wi.z <= 0) return std::nullopt;
    symbol = LobeSymbol::D;
    lobe = diffuseLobe_;
  } else if (uLobe < p.reflection + p.compensation + p.diffuse + p.transmittedCompensation) {
    wi = mirrored(sampleCosineHemisphere(u));
    if (wi.z >= 0) return std::nullopt;
    symbol = transmitSymbol_;
    lobe = transmissionLobe_;
  } else {
    if (delta_) {
      const Rgb value = baseColor_ * transmittance(wo.z, 1);
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
  // mixture density, and each lobe's part is its own value over that density (lobe_interface.h).
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
