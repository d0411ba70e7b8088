#include "renderer/materials/fresnel.h"

#include <gtest/gtest.h>

namespace pathfarm {
namespace {

TEST(FresnelDielectric, NormalIncidence) {
  for (const float n : {1.33f, 1.5f, 2.4f}) {
    const float r0 = ((n - 1) / (n + 1)) * ((n - 1) / (n + 1));
    EXPECT_NEAR(fresnelDielectric(1, n).reflectance, r0, 1e-6f);
    // Same from the dense side.
    EXPECT_NEAR(fresnelDielectric(1, 1 / n).reflectance, r0, 1e-6f);
    EXPECT_NEAR(fresnelDielectric(1, n).cosThetaT, 1, 1e-6f);
  }
}

TEST(FresnelDielectric, GrazingReflectsEverything) {
  EXPECT_NEAR(fresnelDielectric(0, 1.5f).reflectance, 1, 1e-6f);
  EXPECT_GT(fresnelDielectric(0.01f, 1.5f).reflectance, 0.9f);
}

TEST(FresnelDielectric, TotalInternalReflection) {
  // Critical angle from glass: sin = 1 / 1.5, cos = 0.745.
  EXPECT_EQ(fresnelDielectric(0.7f, 1 / 1.5f).reflectance, 1);
  EXPECT_EQ(fresnelDielectric(0.7f, 1 / 1.5f).cosThetaT, 0);
  EXPECT_LT(fresnelDielectric(0.8f, 1 / 1.5f).reflectance, 1);
}

TEST(FresnelDielectric, SnellAndBrewster) {
  const float cosI = 0.6f, n = 1.5f;
  const float sinI = std::sqrt(1 - cosI * cosI);
  const float cosT = fresnelDielectric(cosI, n).cosThetaT;
  EXPECT_NEAR(std::sqrt(1 - cosT * cosT), sinI / n, 1e-6f);
  // At Brewster's angle tan = n the p component vanishes: R = Rs / 2.
  const float cosB = 1 / std::sqrt(1 + n * n);
  const float cosTB = fresnelDielectric(cosB, n).cosThetaT;
  const float rs = (cosB - n * cosTB) / (cosB + n * cosTB);
  EXPECT_NEAR(fresnelDielectric(cosB, n).reflectance, 0.5f * rs * rs, 1e-6f);
}

// Reflectance is the same at the two ends of a refracted ray (Stokes relations).
TEST(FresnelDielectric, SymmetricAcrossTheInterface) {
  for (const float cosI : {0.9f, 0.5f, 0.2f}) {
    const DielectricFresnel outside = fresnelDielectric(cosI, 1.5f);
    EXPECT_NEAR(fresnelDielectric(outside.cosThetaT, 1 / 1.5f).reflectance, outside.reflectance, 1e-5f);
  }
}

TEST(FresnelConductor, NormalIncidence) {
  const float eta = 0.2f, k = 3.9f;
  const float expected = ((eta - 1) * (eta - 1) + k * k) / ((eta + 1) * (eta + 1) + k * k);
  EXPECT_NEAR(fresnelConductor(1, eta, k), expected, 1e-6f);
}

TEST(FresnelConductor, LargeExtinctionIsAPerfectMirror) {
  for (const float cosI : {1.0f, 0.5f, 0.1f}) {
    EXPECT_GT(fresnelConductor(cosI, 1.0f, 1000.0f), 0.999f);
    EXPECT_LE(fresnelConductor(cosI, 1.0f, 1000.0f), 1.0f);
  }
}

TEST(FresnelConductor, ZeroExtinctionIsADielectric) {
  for (const float cosI : {1.0f, 0.7f, 0.3f, 0.05f}) {
    EXPECT_NEAR(fresnelConductor(cosI, 1.5f, 0), fresnelDielectric(cosI, 1.5f).reflectance, 1e-5f);
  }
}

TEST(FresnelConductor, PerChannel) {
  const Rgb f = fresnelConductor(0.5f, Rgb(0.2f, 0.92f, 1.1f), Rgb(3.9f, 2.45f, 2.14f));
  EXPECT_FLOAT_EQ(f.r, fresnelConductor(0.5f, 0.2f, 3.9f));
  EXPECT_FLOAT_EQ(f.g, fresnelConductor(0.5f, 0.92f, 2.45f));
  EXPECT_FLOAT_EQ(f.b, fresnelConductor(0.5f, 1.1f, 2.14f));
  EXPECT_NEAR(fresnelConductor(0, 0.2f, 3.9f), 1, 1e-5f);
}

TEST(FresnelSchlick, EndPoints) {
  const Rgb f0{0.9f, 0.6f, 0.3f};
  EXPECT_FLOAT_EQ(fresnelSchlick(1, f0).g, 0.6f);
  EXPECT_FLOAT_EQ(fresnelSchlick(0, f0).g, 1);
  EXPECT_NEAR(fresnelSchlick(0.5f, f0).b, 0.3f + 0.7f / 32, 1e-6f);
}

// The closed form against direct quadrature of fresnelDielectric, from both sides.
TEST(FresnelDiffuseReflectance, MatchesQuadrature) {
  for (const float eta : {1.1f, 1.33f, 1.5f, 2.4f, 1 / 1.33f, 1 / 1.5f}) {
    const int n = 20000;
    double sum = 0;
    for (int i = 0; i < n; ++i) {
      const double c = (i + 0.5) / n;
      sum += fresnelDielectric(float(c), eta).reflectance * 2 * c;
    }
    EXPECT_NEAR(fresnelDiffuseReflectance(eta), sum / n, 1e-5) << "eta " << eta;
  }
  EXPECT_EQ(fresnelDiffuseReflectance(1), 0);
}

}  // namespace
}  // namespace pathfarm
