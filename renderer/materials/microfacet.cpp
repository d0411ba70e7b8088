#include "renderer/materials/microfacet.h"

namespace pathfarm {

namespace {

// Below this, D overflows float near m = n; such surfaces are mirrors for all purposes.
constexpr float kMinAlpha = 1e-4f;

}  // namespace

MicrofacetDistribution::MicrofacetDistribution(MicrofacetType type, float alpha)
    : type_(type), alpha_(std::max(alpha, kMinAlpha)) {}

float MicrofacetDistribution::D(Vec3f m) const {
  if (m.z <= 0) return 0;
  const float cos2 = m.z * m.z;
  const float alpha2 = alpha_ * alpha_;
  if (type_ == MicrofacetType::GGX) {
    // Walter et al. eq. 33, with cos^4 (alpha^2 + tan^2)^2 = (cos^2 (alpha^2 - 1) + 1)^2.
    const float d = cos2 * (alpha2 - 1) + 1;
    return alpha2 / (kPi * d * d);
  }
  // Beckmann, Walter et al. eq. 25.
  const float tan2 = (1 - cos2) / cos2;
  const float e = std::exp(-tan2 / alpha2);
  // At grazing m the exponential underflows before cos^4 does; keep 0 / 0 out.
  return e == 0 ? 0 : e / (kPi * alpha2 * cos2 * cos2);
}

float MicrofacetDistribution::G1(Vec3f v, Vec3f m) const {
  if (dot(v, m) * v.z <= 0) return 0;
  const float cos2 = v.z * v.z;
  const float tan2 = std::max(0.0f, 1 - cos2) / cos2;
  if (type_ == MicrofacetType::GGX) {
    // Walter et al. eq. 34.
    return 2 / (1 + std::sqrt(1 + alpha_ * alpha_ * tan2));
  }
  // Walter et al. eq. 27: rational fit of the Beckmann Smith term in a = 1 / (alpha tan).
  if (tan2 == 0) return 1;
  const float a = 1 / (alpha_ * std::sqrt(tan2));
  if (a >= 1.6f) return 1;
  return (3.535f * a + 2.181f * a * a) / (1 + 2.276f * a + 2.577f * a * a);
}

Vec3f MicrofacetDistribution::sampleNormal(Vec3f wo, Vec2f u) const {
  const float phi = 2 * kPi * u.y;
  if (type_ == MicrofacetType::Beckmann) {
    // Walter et al. eq. 28: tan^2(theta_m) = -alpha^2 log(1 - u).
    const float tan2 = -alpha_ * alpha_ * std::log(1 - u.x);
    const float cosTheta = 1 / std::sqrt(1 + tan2);
    const float sinTheta = std::sqrt(std::max(0.0f, 1 - cosTheta * cosTheta));
    return {sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta};
  }
  // Heitz 2018: in the configuration stretched to alpha = 1, the visible normals are the
  // visible part of a hemisphere, i.e. a disk projected along the view direction.
  const Vec3f v = normalize(Vec3f{alpha_ * wo.x, alpha_ * wo.y, wo.z});
  const float lensq = v.x * v.x + v.y * v.y;
  const Vec3f t1 = lensq > 0 ? Vec3f{-v.y, v.x, 0} / std::sqrt(lensq) : Vec3f{1, 0, 0};
  const Vec3f t2 = cross(v, t1);
  // A uniform disk point whose far half is squashed onto the part of the disk the
  // hemisphere's silhouette leaves visible.
  const float r = std::sqrt(u.x);
  const float p1 = r * std::cos(phi);
  const float s = 0.5f * (1 + v.z);
  const float p2 = (1 - s) * std::sqrt(std::max(0.0f, 1 - p1 * p1)) + s * r * std::sin(phi);
  const Vec3f h = t1 * p1 + t2 * p2 + v * std::sqrt(std::max(0.0f, 1 - p1 * p1 - p2 * p2));
  // Unstretch back to the rough configuration.
  return normalize(Vec3f{alpha_ * h.x, alpha_ * h.y, std::max(0.0f, h.z)});
}

float MicrofacetDistribution::normalPdf(Vec3f wo, Vec3f m) const {
  if (type_ == MicrofacetType::Beckmann) return D(m) * m.z;
  if (wo.z <= 0) return 0;
  return G1(wo, m) * std::max(0.0f, dot(wo, m)) * D(m) / wo.z;
}

}  // namespace pathfarm
