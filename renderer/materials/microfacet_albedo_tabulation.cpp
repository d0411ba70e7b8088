#include "renderer/materials/microfacet_albedo_tabulation.h"

#include <algorithm>
#include <cmath>
#include <thread>

#include "renderer/materials/fresnel.h"
#include "renderer/materials/microfacet.h"
#include "renderer/materials/specular_albedo_tabulation.h"

namespace pathfarm::microfacet_albedo {
namespace {

using specular_albedo::alphaNode;
using specular_albedo::iorNode;
using specular_albedo::kIor;
using specular_albedo::kMu;
using specular_albedo::meanOverReflections;
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
  return meanOverReflections(distribution, mu, kQuadrature, [&](Vec3f wo, Vec3f m, Vec3f wi) {
    const float pdf = distribution.reflectionPdf(wo, m);
    return pdf > 0 ? distribution.reflectionEval(wo, wi, m) / pdf : 0.0f;
  });
}

// The rough dielectric's albedo is integrated on a coarser grid (it has kIor x kSides times
// the nodes) with its own margin; against a 1000 x 500-point midpoint rule over the sphere between
// the nodes (dielectric_multiple_scattering_test.cpp), it exceeds the albedo by at most 0.015
// and falls short of it by at most 0.0002.
constexpr int kDielectricQuadrature = 24;
constexpr float kDielectricMargin = 0.0095f;

// E = integral over sampled normals m of F D G(wi_r) wo.m / (wo.z pdf(m)) for the reflection
// wi_r plus (1 - F) D G(wi_t) wo.m / (wo.z pdf(m)) for the refraction wi_t: the sampler's
// weights of dielectric.h without the 1 / eta^2 of refraction.
double integrateDielectric(MicrofacetType type, float mu, float alpha, float eta) {
  const MicrofacetDistribution distribution(type, alpha);
  return meanOverSampledNormals(distribution, mu, kDielectricQuadrature, [&](Vec3f wo, Vec3f m) {
    const float cosOM = dot(wo, m), pdf = distribution.normalPdf(wo, m);
    if (!(pdf > 0)) return 0.0;
    const float common = distribution.D(m) * cosOM / (wo.z * pdf);
    const DielectricFresnel fresnel = fresnelDielectric(cosOM, eta);
    double sum = 0;
    const Vec3f reflected = reflect(wo, m);
    if (reflected.z > 0) sum += fresnel.reflectance * common * distribution.G(wo, reflected, m);
    if (fresnel.reflectance < 1) {
      const Vec3f refracted = refract(wo, m, eta, fresnel.cosThetaT);
      if (refracted.z < 0) sum += (1 - fresnel.reflectance) * common * distribution.G(wo, refracted, m);
    }
    return sum;
  });
}

// Fills a row from the albedo at its nodes: raised by the margin, one at most, the grazing
// node the limit of the one next to it; returns the row's exact cosine-weighted average.
template <typename Albedo>
float fillRow(float* row, float margin, const Albedo& albedo) {
  for (int i = 1; i < kMu; ++i) row[i] = std::min(1.0f, float(albedo(muNode(i))) + margin);
  row[0] = row[1];
  return specular_albedo::cosineWeightedAverage(row);
}

}  // namespace

size_t dielectricRows(MicrofacetType type, Side side) {
  return (size_t(distributionIndex(type)) * kSides + size_t(side)) * kIor * kRoughness;
}

Table tabulateDielectric() {
  const size_t rows = size_t(kDistributions) * kSides * kIor * kRoughness;
  Table table{std::vector<float>(rows * kMu), std::vector<float>(rows)};
  // The build waits for this table: each distribution's sides are integrated on a thread
  // of their own (each writes only its own rows, so the result does not depend on them).
  std::vector<std::thread> threads;
  for (const MicrofacetType type : {MicrofacetType::GGX, MicrofacetType::Beckmann}) {
    for (const Side side : {Side::Entering, Side::Leaving}) {
      threads.emplace_back([&table, type, side] {
        for (int k = 0; k < kIor; ++k) {
          const float eta = side == Side::Entering ? iorNode(k) : 1 / iorNode(k);
          for (int j = 0; j < kRoughness; ++j) {
            const size_t r = dielectricRows(type, side) + size_t(k) * kRoughness + j;
            table.average[r] = fillRow(&table.albedo[r * kMu], kDielectricMargin, [&](float mu) {
              return integrateDielectric(type, mu, alphaNode(j), eta);
            });
          }
        }
      });
    }
  }
  for (std::thread& thread : threads) thread.join();
  return table;
}

Table tabulate() {
  Table table{std::vector<float>(size_t(kDistributions) * kRoughness * kMu),
              std::vector<float>(size_t(kDistributions) * kRoughness)};
  for (const MicrofacetType type : {MicrofacetType::GGX, MicrofacetType::Beckmann}) {
    const int d = distributionIndex(type);
    for (int j = 0; j < kRoughness; ++j) {
      // The average is exact for the interpolant, so that the compensation lobe's albedo
      // identity holds for the interpolated E.
      table.average[size_t(d) * kRoughness + j] =
          fillRow(&table.albedo[(size_t(d) * kRoughness + j) * kMu], kMargin,
                  [&](float mu) { return integrate(type, mu, alphaNode(j)); });
    }
  }
  return table;
}

}  // namespace pathfarm::microfacet_albedo
