#include "renderer/materials/microfacet_albedo_tabulation.h"

#include <algorithm>
#include <cmath>

#include "renderer/materials/microfacet.h"
#include "renderer/materials/specular_albedo_tabulation.h"

namespace pathfarm::microfacet_albedo {
namespace {

using specular_albedo::alphaNode;
using specular_albedo::kMu;
using specular_albedo::meanOverSampledNormals;
using specular_albedo::kRoughness;
using specular_albedo::muNode;

// Midpoint quadrature over the normal sampler's unit square.
constexpr int kQuadrature = 128;
// Added to every node, so that the table bounds the albedo from above (nearly) and the
// compensation does not return more than single scattering lost. Against 600 x 600-point
// quadrature on a 40 x 40 grid of (cos theta, sqrt alpha) between the nodes, the
// interpolated table without it fell short of the albedo by up to 0.0065 (near grazing,
// alpha < 0.03); with it, by at most 0.0001 (GGX) and 0.0012 (Beckmann, cos 0.05, alpha
// 0.01), and it exceeds the albedo by at most 0.015: a white metal's furnace lies in
// [0.985, 1.0012].
constexpr float kMargin = 0.0095f;

double integrate(MicrofacetType type, float mu, float alpha) {
  const MicrofacetDistribution distribution(type, alpha);
  return meanOverSampledNormals(distribution, mu, kQuadrature, [&](Vec3f wo, Vec3f m, Vec3f wi) {
    const float pdf = distribution.reflectionPdf(wo, m);
    return pdf > 0 ? distribution.reflectionEval(wo, wi, m) / pdf : 0.0f;
  });
}

}  // namespace

Table tabulate() {
  Table table{std::vector<float>(size_t(kDistributions) * kRoughness * kMu),
              std::vector<float>(size_t(kDistributions) * kRoughness)};
  for (const MicrofacetType type : {MicrofacetType::GGX, MicrofacetType::Beckmann}) {
    const int d = distributionIndex(type);
    for (int j = 0; j < kRoughness; ++j) {
      float* row = &table.albedo[(size_t(d) * kRoughness + j) * kMu];
      // The albedo at grazing incidence is the limit of the nodes next to it.
      for (int i = 1; i < kMu; ++i)
        row[i] = std::min(1.0f, float(integrate(type, muNode(i), alphaNode(j))) + kMargin);
      row[0] = row[1];
      // Exact for the interpolant, so that the compensation lobe's albedo identity holds
      // for the interpolated E.
      table.average[size_t(d) * kRoughness + j] = specular_albedo::cosineWeightedAverage(row);
    }
  }
  return table;
}

}  // namespace pathfarm::microfacet_albedo
