#include "renderer/materials/dielectric.h"

#include "renderer/materials/fresnel.h"

namespace pathfarm {

namespace {

// Seen from below, an interface with ior is the mirror image of one with 1 / ior seen from
// above; mirroring through the tangent plane lets all the math assume wo.z > 0.
struct Oriented {
  Vec3f wo;
  float eta;     // n(side of wi when refracted) / n(side of wo)
  bool flipped;  // directions were mirrored; mirror results back
};

Oriented orient(Vec3f wo, float ior) {
  if (wo.z >= 0) return {wo, ior, false};
  return {{wo.x, wo.y, -wo.z}, 1 / ior, true};
}

Vec3f flipIf(bool flip, Vec3f v) { return flip ? Vec3f{v.x, v.y, -v.z} : v; }

// Snell refraction of wo (wo.m > 0) through the facet m, given the refracted cosine.
Vec3f refract(Vec3f wo, Vec3f m, float eta, float cosThetaT) {
  return -wo / eta + m * (dot(wo, m) / eta - cosThetaT);
}

}  // namespace

std::optional<BsdfSample> SmoothDielectricBsdf::sample(Vec3f wo, float uLobe, Vec2f /*u*/) const {
  if (wo.z == 0) return std::nullopt;
  const Oriented o = orient(wo, ior_);
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

RoughDielectricBsdf::Term RoughDielectricBsdf::evaluate(Vec3f wo, Vec3f wi) const {
  if (wo.z == 0 || wi.z == 0) return {};
  const Oriented o = orient(wo, ior_);
  wi = flipIf(o.flipped, wi);
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
  const Oriented o = orient(wo, ior_);
  const Vec3f m = distribution_.sampleNormal(o.wo, u);
  if (dot(o.wo, m) <= 0) return std::nullopt;
  const DielectricFresnel fresnel = fresnelDielectric(dot(o.wo, m), o.eta);
  Vec3f wi;
  Term term;
  LobeSymbol symbol;
  int lobe;
  if (uLobe < fresnel.reflectance) {
    wi = reflect(o.wo, m);
    if (wi.z <= 0) return std::nullopt;
    term = reflection(o.wo, wi, m, fresnel.reflectance);
    symbol = reflectSymbol_;
    lobe = 0;
  } else {
    wi = refract(o.wo, m, o.eta, fresnel.cosThetaT);
    if (wi.z >= 0) return std::nullopt;
    term = transmission(o.wo, wi, m, 1 - fresnel.reflectance, o.eta);
    symbol = transmitSymbol_;
    lobe = 1;
  }
  return oneLobeSample(flipIf(o.flipped, wi), Rgb(term.value / term.pdf), term.pdf, symbol, false, lobe);
}

}  // namespace pathfarm
