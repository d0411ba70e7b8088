#include "renderer/materials/specular_albedo.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "renderer/materials/fresnel.h"
#include "renderer/materials/microfacet.h"

namespace pathfarm {
namespace {

// Nodes: cos(theta) = (i / (kMu - 1))^2, dense near grazing where Fresnel climbs to one;
// roughness sqrt(alpha) uniform; eta = 1 + (kMaxSpecularAlbedoIor - 1) (k / (kIor - 1))^3,
// dense near 1 where the Fresnel rise at grazing angles changes fastest with eta.
constexpr int kMu = 32, kRoughness = 24, kIor = 24;
// Midpoint quadrature over the visible-normal sampler's unit square, per node.
constexpr int kQuadrature = 16;
// Added to every node: covers the quadrature and interpolation errors. Against adaptive
// integration at 4000 random (cos, roughness, eta), the bound exceeded the albedo by
// 0.006 to 0.015 (cos > 0.09; more near grazing, see below).
constexpr float kMargin = 0.01f;
// Below this node (cos 0.083) the albedo rises steeply towards one as cos(theta) -> 0 and
// the nodes and the margin do not follow it (smooth Fresnel near eta = 1 is the worst
// case). There the bound is at least the chord from 1 at grazing to the node's value,
// which is above the albedo wherever it is convex in cos(theta), as Fresnel is.
constexpr int kGrazingNode = 9;

float muNode(int i) {
  const float s = float(i) / (kMu - 1);
  return s * s;
}
float alphaNode(int j) {
  const float r = float(j) / (kRoughness - 1);
  return r * r;
}
float iorNode(int k) {
  const float s = float(k) / (kIor - 1);
  return 1 + (kMaxSpecularAlbedoIor - 1) * s * s * s;
}

double integrate(float mu, float alpha, float eta) {
  const MicrofacetDistribution distribution(MicrofacetType::GGX, alpha);
  const Vec3f wo{std::sqrt(std::max(0.0f, 1 - mu * mu)), 0, mu};
  double sum = 0;
  for (int a = 0; a < kQuadrature; ++a) {
    for (int b = 0; b < kQuadrature; ++b) {
      const Vec2f u{(a + 0.5f) / kQuadrature, (b + 0.5f) / kQuadrature};
      const Vec3f m = distribution.sampleNormal(wo, u);
      const float cosOM = dot(wo, m);
      if (cosOM <= 0) continue;
      const Vec3f wi = reflect(wo, m);
      if (wi.z <= 0) continue;
      sum += fresnelDielectric(cosOM, eta).reflectance * distribution.G1(wi, m);
    }
  }
  return sum / (kQuadrature * kQuadrature);
}

struct Table {
  std::vector<float> albedo;   // [ior][roughness][mu]
  std::vector<float> average;  // [ior][roughness]

  Table() : albedo(size_t(kIor) * kRoughness * kMu), average(size_t(kIor) * kRoughness) {
    for (int k = 0; k < kIor; ++k) {
      for (int j = 0; j < kRoughness; ++j) {
        float* row = &albedo[(size_t(k) * kRoughness + j) * kMu];
        // At grazing incidence everything is reflected in the limit; one is a safe bound.
        row[0] = 1;
        for (int i = 1; i < kMu; ++i)
          row[i] = std::min(1.0f, float(integrate(muNode(i), alphaNode(j), iorNode(k))) + kMargin);
        for (int i = 1; i < kGrazingNode; ++i) {
          const float chord = 1 - (1 - row[kGrazingNode]) * muNode(i) / muNode(kGrazingNode);
          row[i] = std::max(row[i], chord);
        }
        // 2 integral E mu dmu of the piecewise linear interpolant, exact per segment:
        // 2 integral_a^b L(mu) mu dmu = (b - a) / 3 (y_a (2a + b) + y_b (a + 2b)).
        double sum = 0;
        for (int i = 0; i + 1 < kMu; ++i) {
          const double a = muNode(i), b = muNode(i + 1);
          sum += (b - a) / 3 * (row[i] * (2 * a + b) + row[i + 1] * (a + 2 * b));
        }
        average[size_t(k) * kRoughness + j] = float(sum);
      }
    }
  }
};

const Table& table() {
  static const Table t;
  return t;
}

// Cell index and weight of the upper node for x in [0, n - 1].
struct Cell {
  int index;
  float t;
};
Cell cell(float x, int n) {
  x = std::clamp(x, 0.0f, float(n - 1));
  const int index = std::min(int(x), n - 2);
  return {index, x - float(index)};
}

Cell roughnessCell(float alpha) { return cell(std::sqrt(std::max(0.0f, alpha)) * (kRoughness - 1), kRoughness); }
Cell iorCell(float eta) {
  return cell(std::cbrt(std::max(0.0f, (eta - 1) / (kMaxSpecularAlbedoIor - 1))) * (kIor - 1), kIor);
}

// Bilinear in roughness and ior over a quantity f(ior node, roughness node); the same
// weights for the albedo and its average keep the average exact for the interpolant.
template <typename F>
float interpolate(Cell r, Cell n, const F& f) {
  const auto along = [&](int k) { return (1 - r.t) * f(k, r.index) + r.t * f(k, r.index + 1); };
  return (1 - n.t) * along(n.index) + n.t * along(n.index + 1);
}

}  // namespace

float specularAlbedoBound(float cosTheta, float alpha, float eta) {
  const Table& t = table();
  // Linear in cos(theta) between the nodes, as the average assumes; the node spacing is
  // what is quadratic.
  const float mu = std::clamp(cosTheta, 0.0f, 1.0f);
  const int i = cell(std::sqrt(mu) * (kMu - 1), kMu).index;
  const float a = muNode(i), b = muNode(i + 1);
  const float w = std::clamp((mu - a) / (b - a), 0.0f, 1.0f);
  return interpolate(roughnessCell(alpha), iorCell(eta), [&](int k, int j) {
    const float* row = &t.albedo[(size_t(k) * kRoughness + j) * kMu];
    return (1 - w) * row[i] + w * row[i + 1];
  });
}

float averageSpecularAlbedoBound(float alpha, float eta) {
  const Table& t = table();
  return interpolate(roughnessCell(alpha), iorCell(eta),
                     [&](int k, int j) { return t.average[size_t(k) * kRoughness + j]; });
}

}  // namespace pathfarm
