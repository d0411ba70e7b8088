// KHR_materials_specular on the metallic-roughness BSDF: the dielectric reflectance goes
// from s min(c F0, 1) at normal incidence to s at grazing. Checked against a Lambertian
// in closed form (s = 0), against the exact Fresnel equations on smooth surfaces, and in
// a white furnace over the factors. The shared suites (bsdf_chi2_test.cpp, bsdf_test.cpp)
// sample, evaluate and swap directions of two specular cases (bsdf_test_support.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "renderer/materials/bsdf.h"
#include "tests/renderer/materials/bsdf_test_support.h"

namespace pathfarm::bsdftest {
namespace {

// Unpolarized reflectance of a dielectric of index eta from outside, in double.
double exactFresnel(double cosI, double eta) {
  const double sin2T = (1 - cosI * cosI) / (eta * eta);
  if (sin2T >= 1) return 1;
  const double cosT = std::sqrt(1 - sin2T);
  const double rs = (cosI - eta * cosT) / (cosI + eta * cosT);
  const double rp = (eta * cosI - cosT) / (eta * cosI + cosT);
  return (rs * rs + rp * rp) / 2;
}

TEST(MetallicRoughnessSpecular, WithoutSpecularTheDielectricIsLambertian) {
  const Rgb base{0.8f, 0.5f, 0.2f};
  const Material m = withSpecular(metallicRoughness(0.4f, 0, 0), 0, Rgb(1));
  const Bsdf bsdf(m, base, kRoughnessThreshold);
  for (const float cosO : {0.9f, 0.5f, 0.1f}) {
    for (const float cosI : {0.95f, 0.3f, 0.05f}) {
      const Vec3f wo = directionFromCos(cosO, 0.2f), wi = directionFromCos(cosI, 2.5f);
      const Rgb f = bsdf.eval(wo, wi);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(f[c], base[c] * cosI / kPi, 1e-6f) << cosO << " " << cosI;
    }
    const auto s = bsdf.sample(directionFromCos(cosO), 0.3f, {0.6f, 0.2f});
    ASSERT_TRUE(s);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(s->weight[c], base[c], 1e-5f);
  }
}

// A smooth opaque sheet reflects F' = s (c0 + (1 - c0) (F - F0) / (1 - F0)) as a mirror.
TEST(MetallicRoughnessSpecular, ASmoothSheetReflectsTheRemappedFresnel) {
  const float s = 0.7f;
  const Rgb color{0, 1, 2.5f};
  const double eta = 1.45, f0 = exactFresnel(1, eta);
  Material m = withSpecular(metallicRoughness(0, 0, 0, 1.45f), s, color);
  const Bsdf bsdf(m, Rgb(1), kRoughnessThreshold);
  for (const float cosTheta : {1.0f, 0.6f, 0.2f, 0.02f}) {
    const Vec3f wo = directionFromCos(cosTheta, 0.7f);
    const auto mirror = bsdf.sample(wo, 0.0f, {0.5f, 0.5f});  // the first lobe: the mirror
    ASSERT_TRUE(mirror && mirror->delta);
    const double f = exactFresnel(cosTheta, eta);
    for (int c = 0; c < 3; ++c) {
      const double c0 = std::min(color[c] * f0, 1.0);
      const double expected = s * (c0 + (1 - c0) * (f - f0) / (1 - f0));
      // The sample carries the mirror's value over the probability of choosing it.
      EXPECT_NEAR(mirror->weight[c] * mirror->pdf, expected, 2e-5) << "cos " << cosTheta << " channel " << c;
    }
  }
}

// The furnace over the extension's factors, with and without transmission: no channel
// reflects more than it receives, and without a specular layer a white sheet keeps all.
TEST(MetallicRoughnessSpecular, WhiteFurnaceNeverExceedsOne) {
  for (const float specular : {0.0f, 0.5f, 1.0f}) {
    for (const Rgb color : {Rgb(0), Rgb(1), Rgb(3, 1, 0.2f), Rgb(40)}) {
      for (const float roughness : {0.1f, 0.5f, 1.0f}) {
        for (const float transmission : {0.0f, 0.5f}) {
          const Material m = withSpecular(metallicRoughness(roughness, 0, transmission), specular, color);
          for (const float cosTheta : {0.9f, 0.4f, 0.08f}) {
            const Estimate e = albedo(m, Rgb(1), directionFromCos(cosTheta, 1.1f), 20000);
            for (int c = 0; c < 3; ++c) {
              EXPECT_LE(e.mean[c], 1 + 3 * e.stdError[c] + 1e-5f)
                  << "specular " << specular << " roughness " << roughness << " transmission " << transmission
                  << " cos " << cosTheta << " channel " << c;
            }
            if (specular == 0 && transmission == 0) EXPECT_NEAR(e.mean.g, 1, 1e-4f) << "cos " << cosTheta;
          }
        }
      }
    }
  }
}

}  // namespace
}  // namespace pathfarm::bsdftest
