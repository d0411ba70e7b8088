// The multiple-scattering compensation (multiple_scattering.h) against independent
// integration: its table bounds the single-scattering albedo integrated over a grid of
// incident directions (not the normal sampler the table used) closely from above, its lobe
// returns exactly what single scattering loses, and white metals of every roughness keep
// their energy; sampling and reciprocity are checked with the other lobes
// (bsdf_chi2_test.cpp, bsdf_test.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "renderer/materials/bsdf.h"
#include "renderer/materials/microfacet.h"
#include "renderer/materials/multiple_scattering.h"
#include "renderer/math/sampling.h"
#include "tests/renderer/materials/bsdf_test_support.h"

namespace pathfarm {
namespace {

using bsdftest::directionalAlbedo;
using bsdftest::directionFromCos;
using bsdftest::Estimate;
using bsdftest::makeMaterial;
using bsdftest::metallicRoughness;

// Integral over the hemisphere of f(wi) (already times cos(wi)), by a midpoint rule in
// (cos theta, phi): d omega = d cos d phi.
template <typename F>
double overHemisphere(F f, int steps = 400) {
  double sum = 0;
  for (int a = 0; a < steps; ++a) {
    const float cosTheta = (a + 0.5f) / steps;
    const float sinTheta = std::sqrt(1 - cosTheta * cosTheta);
    for (int b = 0; b < steps; ++b) {
      const float phi = 2 * kPi * (b + 0.5f) / steps;
      sum += f(Vec3f{sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta});
    }
  }
  return sum * 2 * kPi / (double(steps) * steps);
}

Vec3f fromCos(float cosTheta) { return {std::sqrt(1 - cosTheta * cosTheta), 0, cosTheta}; }

TEST(MultipleScattering, TableBoundsTheSingleScatteringAlbedoClosely) {
  for (const MicrofacetType type : {MicrofacetType::GGX, MicrofacetType::Beckmann}) {
    for (const float alpha : {0.07f, 0.3f, 0.55f, 1.0f}) {  // off the roughness nodes but 1
      const MicrofacetDistribution distribution(type, alpha);
      const MultipleScattering multiple(type, alpha);
      for (const float cosTheta : {0.95f, 0.6f, 0.3f, 0.12f}) {
        const Vec3f wo = fromCos(cosTheta);
        const double albedo = overHemisphere([&](Vec3f wi) {
          return double(distribution.reflectionEval(wo, wi, normalize(wo + wi)));
        }, 800);
        // An upper bound (the compensation must not create light) within the table's margin.
        EXPECT_GE(multiple.albedo(cosTheta), albedo - 2e-3) << int(type) << " alpha " << alpha << " cos " << cosTheta;
        EXPECT_LE(multiple.albedo(cosTheta), albedo + 0.016) << int(type) << " alpha " << alpha << " cos " << cosTheta;
      }
    }
  }
  // Smooth surfaces lose nothing; GGX of alpha 1 seen head-on keeps about a third.
  EXPECT_NEAR(MultipleScattering(MicrofacetType::GGX, 0).albedo(0.7f), 1.0f, 1e-3f);
  EXPECT_NEAR(MultipleScattering(MicrofacetType::GGX, 1).albedo(1.0f), 0.31f, 0.02f);
}

// A degenerate direction (a Metropolis mutation's, whose cosine came out NaN) read past
// the albedo table and crashed the benchmark; it is a grazing albedo and no lobe.
TEST(MultipleScattering, ANaNCosineReadsTheTableAndScattersNothing) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const MultipleScattering rough(MicrofacetType::GGX, 0.6f);
  EXPECT_EQ(rough.albedo(nan), rough.albedo(0.0f));
  EXPECT_EQ(rough.eval(nan, 0.5f), 0.0f);
  EXPECT_EQ(rough.eval(0.5f, nan), 0.0f);
  EXPECT_GT(rough.eval(0.5f, 0.5f), 0.0f);
}

TEST(MultipleScattering, LobeReturnsWhatSingleScatteringLoses) {
  for (const float alpha : {0.2f, 0.6f, 1.0f}) {
    const MultipleScattering multiple(MicrofacetType::GGX, alpha);
    for (const float cosTheta : {0.9f, 0.4f, 0.1f}) {
      const double returned = overHemisphere([&](Vec3f wi) { return double(multiple.eval(cosTheta, wi.z)); });
      EXPECT_NEAR(returned, multiple.lost(cosTheta), 2e-3) << "alpha " << alpha << " cos " << cosTheta;
      EXPECT_FLOAT_EQ(multiple.eval(cosTheta, 0.3f) / 0.3f, multiple.eval(0.3f, cosTheta) / cosTheta);
    }
  }
  // White light reflects as white; coloured Fresnel gives a deeper colour than its average.
  const MultipleScattering rough(MicrofacetType::GGX, 1);
  EXPECT_FLOAT_EQ(rough.tint(Rgb(1)).g, 1.0f);
  const Rgb gold = rough.tint(Rgb(1.0f, 0.8f, 0.3f));
  EXPECT_LT(gold.b, 0.3f);
  EXPECT_LT(gold.g, 0.8f);
  EXPECT_NEAR(schlickFresnelAverage(Rgb(0)).r, 1.0f / 21, 1e-7f);
  // Conductor Fresnel's average against a fine midpoint rule of 2 F(mu) mu.
  const Rgb eta{0.2f, 0.92f, 1.1f}, k{3.9f, 2.45f, 2.14f};
  double fine = 0;
  for (int n = 0; n < 20000; ++n) {
    const float mu = (n + 0.5f) / 20000;
    fine += 2 * fresnelConductor(mu, eta, k).g * mu / 20000;
  }
  EXPECT_NEAR(conductorFresnelAverage(eta, k).g, fine, 1e-4);
}

// A white material in the furnace reads at least 0.97 and never above one.
void expectKeepsItsEnergy(const std::string& name, const Material& material) {
  for (const float cosTheta : {0.9f, 0.5f, 0.2f}) {
    const Estimate e = directionalAlbedo(material, Rgb(1), directionFromCos(cosTheta), 40000, 11);
    EXPECT_GE(e.mean.g, 0.97f) << name << " cos " << cosTheta;
    EXPECT_LE(e.mean.g, 1 + 3 * e.stdError.g + 1e-5f) << name << " cos " << cosTheta;
  }
}

// The figure: a white metal in the furnace reads at least 0.97 at every roughness
// (single scattering alone: 0.31 at GGX alpha 1), and never above one.
TEST(MultipleScattering, WhiteMetalsKeepTheirEnergyAtEveryRoughness) {
  using MT = MaterialType;
  std::vector<std::pair<std::string, Material>> metals;
  for (const float alpha : {0.1f, 0.4f, 0.7f, 1.0f}) {
    for (const MicrofacetType type : {MicrofacetType::GGX, MicrofacetType::Beckmann}) {
      Material m = makeMaterial(MT::RoughConductor, type, alpha);
      m.useSpecularColor = true;  // Schlick with F0 = 1
      metals.emplace_back("rough_conductor alpha " + std::to_string(alpha) + (type == MicrofacetType::GGX ? " GGX" : " Beckmann"), m);
    }
    metals.emplace_back("metallic_roughness roughness " + std::to_string(std::sqrt(alpha)),
                        metallicRoughness(std::sqrt(alpha), 1, 0));
  }
  for (const auto& [name, material] : metals) expectKeepsItsEnergy(name, material);
}

// glTF's thin-walled transmission: the facets' lost light leaves on both sides of the sheet
// (single scattering alone keeps 0.32 of it at roughness 1, cos 0.9).
TEST(MultipleScattering, WhiteThinWalledGlassKeepsItsEnergyAtEveryRoughness) {
  for (const float roughness : {0.3f, 0.6f, 0.8f, 1.0f}) {
    for (const float ior : {1.5f, 2.4f}) {
      expectKeepsItsEnergy("roughness " + std::to_string(roughness) + " ior " + std::to_string(ior),
                           metallicRoughness(roughness, 0, 1, ior));
    }
  }
}

}  // namespace
}  // namespace pathfarm
