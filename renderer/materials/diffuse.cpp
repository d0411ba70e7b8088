#include "renderer/materials/diffuse.h"

#include "renderer/math/sampling.h"

namespace pathfarm {

Rgb DiffuseBsdf::eval(Vec3f wo, Vec3f wi) const {
  if (wo.z <= 0 || wi.z <= 0) return {};
  return albedo_ * (kInvPi * wi.z);
}

float DiffuseBsdf::pdf(Vec3f wo, Vec3f wi) const {
  if (wo.z <= 0 || wi.z <= 0) return 0;
  return cosineHemispherePdf(wi.z);
}

std::optional<BsdfSample> DiffuseBsdf::sample(Vec3f wo, float /*uLobe*/, Vec2f u) const {
  if (wo.z <= 0) return std::nullopt;
  const Vec3f wi = sampleCosineHemisphere(u);
  if (wi.z <= 0) return std::nullopt;
  return oneLobeSample(wi, albedo_, cosineHemispherePdf(wi.z), LobeSymbol::D, false, 0);
}

}  // namespace pathfarm
