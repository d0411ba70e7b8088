// The rough dielectric's multiple-scattering compensation (multiple_scattering.h) against
// independent integration: its table bounds the single-scattering flux albedo closely from
// above on both sides, its lobes return exactly what single scattering loses and are
// reciprocal across the interface, and white glass of every roughness keeps its energy.
// Sampling against eval and pdf is checked with the other materials (bsdf_chi2_test.cpp,
// bsdf_test.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "renderer/materials/fresnel.h"
#include "renderer/materials/microfacet.h"
#include "renderer/materials/multiple_scattering.h"
#include "tests/renderer/materials/bsdf_test_support.h"

namespace pathfarm::glass_compensation_test {
namespace {

using bsdftest::directionalAlbedo;
using bsdftest::directionFromCos;
using bsdftest::Estimate;
using bsdftest::makeMaterial;
using Side = DielectricMultipleScattering::Side;

// Integral over the sphere of f(wi) (already times |cos(wi)|), by a midpoint rule in
// (cos theta, phi) over each hemisphere: d omega = d cos d phi.
template <typename F>
double overSphere(F f, int steps) {
  double sum = 0;
  for (int a = 0; a < 2 * steps; ++a) {
    const float cosTheta = -1 + (a + 0.5f) / steps;
    const float sinTheta = std::sqrt(1 - cosTheta * cosTheta);
    for (int b = 0; b < steps; ++b) {
      const float phi = 2 * kPi * (b + 0.5f) / steps;
      sum += f(Vec3f{sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta});
    }
  }
  return sum * 2 * kPi / (double(steps) * steps);
}

// Walter et al. 2007, eqs. 20 and 21, as flux (times eta^2 across the interface) and times
// |cos(wi)|, for wo above the surface and eta = n(below) / n(above).
double singleScatteringFlux(const MicrofacetDistribution& d, Vec3f wo, Vec3f wi, float eta) {
  if (wi.z > 0) {
    const Vec3f m = normalize(wo + wi);
    return fresnelDielectric(dot(wo, m), eta).reflectance * d.D(m) * d.G(wo, wi, m) / (4 * wo.z);
  }
  Vec3f m = normalize(wo + wi * eta);
  if (m.z < 0) m = -m;
  const double cosOM = dot(wo, m), cosIM = dot(wi, m);
  if (cosOM <= 0 || cosIM >= 0) return 0;
  const double denom = eta * cosIM + cosOM;
  return (1 - fresnelDielectric(float(cosOM), eta).reflectance) * d.D(m) * d.G(wo, wi, m) * cosOM *
         std::abs(cosIM) * eta * eta / (wo.z * denom * denom);
}

TEST(GlassCompensation, TableBoundsTheSingleScatteringAlbedoClosely) {
  for (const MicrofacetType type : {MicrofacetType::GGX, MicrofacetType::Beckmann}) {
    for (const float alpha : {0.07f, 0.3f, 0.55f, 1.0f}) {  // off the roughness nodes but 1
      const MicrofacetDistribution distribution(type, alpha);
      for (const float ior : {1.33f, 2.4f}) {
        const DielectricMultipleScattering multiple(type, alpha, ior);
        for (const Side side : {Side::Entering, Side::Leaving}) {
          const float eta = side == Side::Entering ? ior : 1 / ior;
          for (const float cosTheta : {0.95f, 0.6f, 0.3f, 0.12f}) {
            const Vec3f wo = directionFromCos(cosTheta, 0);
            const double albedo =
                overSphere([&](Vec3f wi) { return singleScatteringFlux(distribution, wo, wi, eta); }, 500);
            const std::string where = std::to_string(int(type)) + " alpha " + std::to_string(alpha) + " ior " +
                                      std::to_string(ior) + " side " + std::to_string(int(side)) + " cos " +
                                      std::to_string(cosTheta);
            // An upper bound (the compensation must not create light) within the margin.
            EXPECT_GE(multiple.albedo(side, cosTheta), albedo - 3e-3) << where;
            EXPECT_LE(multiple.albedo(side, cosTheta), albedo + 0.02) << where;
          }
        }
      }
    }
  }
}

TEST(GlassCompensation, LobesReturnWhatSingleScatteringLosesAndAreReciprocal) {
  for (const float alpha : {0.2f, 0.6f, 1.0f}) {
    for (const float ior : {1.2f, 1.5f, 2.4f}) {
      const DielectricMultipleScattering multiple(MicrofacetType::GGX, alpha, ior);
      for (const Side side : {Side::Entering, Side::Leaving}) {
        const Side other = side == Side::Entering ? Side::Leaving : Side::Entering;
        // n^2 of each side's medium, outside 1.
        const float n2 = side == Side::Entering ? 1 : ior * ior, n2Other = side == Side::Entering ? ior * ior : 1;
        for (const float cosTheta : {0.9f, 0.4f, 0.1f}) {
          const double returned = overSphere(
              [&](Vec3f wi) {
                return wi.z > 0 ? double(multiple.reflection(side, cosTheta, wi.z))
                                : double(multiple.transmission(side, cosTheta, -wi.z));
              },
              300);
          EXPECT_NEAR(returned, multiple.lost(side, cosTheta), 2e-3) << "alpha " << alpha << " ior " << ior;
          // Flux g across the interface: g(wo, wi) / n(wi)^2 = g(wi, wo) / n(wo)^2.
          const float cosI = 0.3f;
          EXPECT_NEAR(multiple.transmission(side, cosTheta, cosI) / cosI / n2Other,
                      multiple.transmission(other, cosI, cosTheta) / cosTheta / n2, 1e-6)
              << "alpha " << alpha << " ior " << ior;
          EXPECT_FLOAT_EQ(multiple.reflection(side, cosTheta, cosI) / cosI,
                          multiple.reflection(side, cosI, cosTheta) / cosTheta);
        }
        EXPECT_GE(multiple.reflectedShare(side), 0);
        EXPECT_LE(multiple.reflectedShare(side), 1);
      }
      // From outside most of the lost light is refracted into the glass, as by a smooth
      // interface under uniform light.
      EXPECT_GT(1 - multiple.reflectedShare(Side::Entering), 0.5f);
    }
  }
}

// White glass in the furnace: the flux it reflects and refracts adds up to at least 0.97 at
// every roughness, from either side (single scattering alone: down to 0.31, GGX alpha 1
// seen from inside at cos 0.2), and never above one.
TEST(GlassCompensation, WhiteGlassKeepsItsEnergyAtEveryRoughness) {
  for (const MicrofacetType type : {MicrofacetType::GGX, MicrofacetType::Beckmann}) {
    for (const float alpha : {0.1f, 0.4f, 0.7f, 1.0f}) {
      for (const float ior : {1.33f, 1.5f, 2.4f}) {
        Material m = makeMaterial(MaterialType::RoughDielectric, type, alpha);
        m.ior = ior;
        for (const float cosTheta : {0.9f, 0.5f, 0.2f, -0.9f, -0.5f, -0.2f}) {
          const Estimate e = directionalAlbedo(m, Rgb(1), directionFromCos(cosTheta), 20000, 13);
          const std::string where = std::to_string(int(type)) + " alpha " + std::to_string(alpha) + " ior " +
                                    std::to_string(ior) + " cos " + std::to_string(cosTheta);
          EXPECT_GE(e.mean.g, 0.97f) << where;
          EXPECT_LE(e.mean.g, 1 + 3 * e.stdError.g + 1e-5f) << where;
        }
      }
    }
  }
}

}  // namespace
}  // namespace pathfarm::glass_compensation_test
