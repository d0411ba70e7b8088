#include "renderer/materials/specular_albedo_tabulation.h"

#include <algorithm>
#include <cmath>

#include "renderer/materials/fresnel.h"
#include "renderer/materials/microfacet.h"

namespace pathfarm::specular_albedo {
namespace {

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

double integrate(float mu, float alpha, float eta, Reflectance reflectance) {
  const MicrofacetDistribution distribution(MicrofacetType::GGX, alpha);
  const float subtracted = reflectance == Reflectance::Excess ? fresnelDielectric(1, eta).reflectance : 0.0f;
  // The visible-normal sampler's weight for a reflection is F G1(wi) (microfacet.h).
  return meanOverReflections(distribution, mu, kQuadrature, [&](Vec3f wo, Vec3f m, Vec3f wi) {
    return (fresnelDielectric(dot(wo, m), eta).reflectance - subtracted) * distribution.G1(wi, m);
  });
}

}  // namespace

float cosineWeightedAverage(const float* row) {
  // Exact per segment: 2 integral_a^b L(mu) mu dmu = (b - a) / 3 (y_a (2a + b) + y_b (a + 2b)).
  double sum = 0;
  for (int i = 0; i + 1 < kMu; ++i) {
    const double a = muNode(i), b = muNode(i + 1);
    sum += (b - a) / 3 * (row[i] * (2 * a + b) + row[i + 1] * (a + 2 * b));
  }
  return float(sum);
}

Table tabulate(Reflectance reflectance) {
  Table table{std::vector<float>(size_t(kIor) * kRoughness * kMu), std::vector<float>(size_t(kIor) * kRoughness)};
  for (int k = 0; k < kIor; ++k) {
    for (int j = 0; j < kRoughness; ++j) {
      float* row = &table.albedo[(size_t(k) * kRoughness + j) * kMu];
      // At grazing incidence everything is reflected in the limit; one is a safe bound.
      row[0] = 1;
      for (int i = 1; i < kMu; ++i)
        row[i] = std::min(1.0f, float(integrate(muNode(i), alphaNode(j), iorNode(k), reflectance)) + kMargin);
      for (int i = 1; i < kGrazingNode; ++i) {
        const float chord = 1 - (1 - row[kGrazingNode]) * muNode(i) / muNode(kGrazingNode);
        row[i] = std::max(row[i], chord);
      }
      table.average[size_t(k) * kRoughness + j] = cosineWeightedAverage(row);
    }
  }
  return table;
}

}  // namespace pathfarm::specular_albedo
