#include "renderer/materials/dielectric.h"

#include <algorithm>

#include "renderer/materials/fresnel.h"
#include "renderer/math/sampling.h"

namespace pathfarm {

// Seen from below, an interface with ior is the mirror image of one with 1 / ior seen from
// above; mirroring through the tangent plane lets all the math assume wo.z > 0.
struct GlassOrientation {
  Vec3f wo;
  float eta;     // n(side of wi when refracted) / n(side of wo)
  bool flipped;  // directions were mirrored; mirror results back
  DielectricMultipleScattering::Side side() const {
    return flipped ? DielectricMultipleScattering::Side::Leaving : DielectricMultipleScattering::Side::Entering;
  }
};

namespace {

GlassOrientation orient(Vec3f wo, float ior) {
  if (wo.z >= 0) return {wo, ior, false};
  return {{wo.x, wo.y, -wo.z}, 1 / ior, true};
}

Vec3f flipIf(bool flip, Vec3f v) { return flip ? Vec3f{v.x, v.y, -v.z} : v; }

}  // namespace

std::optional<BsdfSample> SmoothDielectricBsdf::sample(Vec3f wo, float uLobe, Vec2f /*u*/) const {
  if (wo.z == 0) return std::nullopt;
  const GlassOrientation o = orient(wo, ior_);
  const DielectricFresnel fresnel = fresnelDielectric(o.wo.z, o.eta);
  if (uLobe < fresnel.reflectance) {
    return oneLobeSample(flipIf(o.flipped, {-o.wo.x, -o.wo.y, o.wo.z}), Rgb(1), fresnel.reflectance,
                         LobeSymbol::R, true, 0);
  }
  const Vec3f wi = refract(o.wo, {0, 0, 1}, o.eta, fresnel.cosThetaT);
  return oneLobeSample(flipIf(o.flipped, wi), Rgb(1 / (o.eta * o.eta)), 1 - fresnel.reflectance, LobeSymbol::T,
                       true, 1);
}

RoughDielectricBsdf::RoughDielectricBsdf(const Material& material, float roughnessThreshold)
    : ior_(material.ior),
      distribution_(material.distribution, material.alpha),
      multiple_(material.distribution, material.alpha, material.ior),
      reflectSymbol_(glossyLobeSymbol(material.alpha, roughnessThreshold, LobeSymbol::R)),
      transmitSymbol_(glossyLobeSymbol(material.alpha, roughnessThreshold, LobeSymbol::T)) {}

RoughDielectricBsdf::Term RoughDielectricBsdf::reflection(Vec3f wo, Vec3f wi, Vec3f m,
                                                          float lobeProbability) const {
  return {lobeProbability * distribution_.reflectionEval(wo, wi, m),
          lobeProbability * distribution_.reflectionPdf(wo, m)};
}

RoughDielectricBsdf::Term RoughDielectricBsdf::transmission(Vec3f wo, Vec3f wi, Vec3f m,
                                                            float lobeProbability, float eta) const {
  const float cosOM = dot(wo, m), cosIM = dot(wi, m);
  const float denom = eta * cosIM + cosOM;
  // d(omega_m) / d(omega_i) for refraction (Walter et al. eq. 17, with wi the sampled side).
  const float jacobian = eta * eta * std::abs(cosIM) / (denom * denom);
  // Walter et al. eq. 21 for radiance times |cos(wi)|:
  //   (1 - F) D G |wi.m| wo.m / (wo.z (eta wi.m + wo.m)^2),
  // written through the Jacobian to show the 1 / eta^2 radiance scaling across the interface.
  const float value = lobeProbability * distribution_.D(m) * distribution_.G(wo, wi, m) * cosOM * jacobian /
                      (wo.z * eta * eta);
  return {value, lobeProbability * distribution_.normalPdf(wo, m) * jacobian};
}

RoughDielectricBsdf::Term RoughDielectricBsdf::singleScattering(const GlassOrientation& o, Vec3f wi) const {
  if (wi.z > 0) {
    const Vec3f m = normalize(o.wo + wi);
    return reflection(o.wo, wi, m, fresnelDielectric(dot(o.wo, m), o.eta).reflectance);
  }
  // Generalized half vector (Walter et al. eq. 16), oriented to the upper hemisphere.
  const Vec3f h = o.wo + wi * o.eta;
  const float len = length(h);
  if (len == 0) return {};
  const Vec3f m = h.z > 0 ? h / len : -h / len;
  // Only facets that wo sees from above and wi from below refract one into the other.
  if (dot(o.wo, m) <= 0 || dot(wi, m) >= 0) return {};
  return transmission(o.wo, wi, m, 1 - fresnelDielectric(dot(o.wo, m), o.eta).reflectance, o.eta);
}

float RoughDielectricBsdf::compensationShare(const GlassOrientation& o) const {
  // What single scattering loses at wo; below one, so that the facets are always sampled too.
  return std::clamp(multiple_.lost(o.side(), o.wo.z), 0.0f, 0.999f);
}

RoughDielectricBsdf::Term RoughDielectricBsdf::evaluate(const GlassOrientation& o, Vec3f wi) const {
  if (o.wo.z == 0 || wi.z == 0) return {};
  const Term single = singleScattering(o, wi);
  const float share = compensationShare(o);
  const float reflected = multiple_.reflectedShare(o.side());
  // The compensation's refraction is flux, as the tables are; radiance across the interface
  // scales by 1 / eta^2 as in transmission().
  const Term compensation =
      wi.z > 0 ? Term{multiple_.reflection(o.side(), o.wo.z, wi.z), reflected * cosineHemispherePdf(wi.z)}
               : Term{multiple_.transmission(o.side(), o.wo.z, -wi.z) / (o.eta * o.eta),
                      (1 - reflected) * cosineHemispherePdf(-wi.z)};
  return {single.value + compensation.value, (1 - share) * single.pdf + share * compensation.pdf};
}

RoughDielectricBsdf::Term RoughDielectricBsdf::evaluate(Vec3f wo, Vec3f wi) const {
  const GlassOrientation o = orient(wo, ior_);
  return evaluate(o, flipIf(o.flipped, wi));
}

LobeValues RoughDielectricBsdf::evalLobes(Vec3f wo, Vec3f wi) const {
  // The side test of evaluate(), which reflects exactly when wi, mirrored along with wo,
  // has z > 0.
  const float side = orient(wo, ior_).flipped ? -wi.z : wi.z;
  LobeValues v;
  v.value[side > 0 ? 0 : 1] = Rgb(evaluate(wo, wi).value);
  return v;
}

std::optional<BsdfSample> RoughDielectricBsdf::sample(Vec3f wo, float uLobe, Vec2f u) const {
  if (wo.z == 0) return std::nullopt;
  const GlassOrientation o = orient(wo, ior_);
  const float share = compensationShare(o);
  Vec3f wi;
  if (uLobe < share) {
    // The compensation: the cosine hemisphere on the side its light leaves by.
    wi = sampleCosineHemisphere(u);
    if (uLobe >= share * multiple_.reflectedShare(o.side())) wi.z = -wi.z;
  } else {
    const Vec3f m = distribution_.sampleNormal(o.wo, u);
    if (dot(o.wo, m) <= 0) return std::nullopt;
    const DielectricFresnel fresnel = fresnelDielectric(dot(o.wo, m), o.eta);
    if ((uLobe - share) / (1 - share) < fresnel.reflectance) {
      wi = reflect(o.wo, m);
      if (wi.z <= 0) return std::nullopt;
    } else {
      wi = refract(o.wo, m, o.eta, fresnel.cosThetaT);
      if (wi.z >= 0) return std::nullopt;
    }
  }
  const Term term = evaluate(o, wi);
  if (!(term.pdf > 0)) return std::nullopt;
  const bool reflected = wi.z > 0;
  return oneLobeSample(flipIf(o.flipped, wi), Rgb(term.value / term.pdf), term.pdf,
                       reflected ? reflectSymbol_ : transmitSymbol_, false, reflected ? 0 : 1);
}

}  // namespace pathfarm
