#include "renderer/materials/microfacet.h"

#include <gtest/gtest.h>

#include "tests/renderer/materials/bsdf_test_support.h"

namespace pathfarm::bsdftest {
namespace {

class MicrofacetDistributionTest : public ::testing::TestWithParam<MicrofacetType> {};

// Projected microfacet area equals the macro area: integral of D(m) cos(theta_m) = 1
// (Walter et al. 2007, section 3).
TEST_P(MicrofacetDistributionTest, ProjectedAreaIsOne) {
  for (const float alpha : {0.1f, 0.3f, 0.8f}) {
    const MicrofacetDistribution d(GetParam(), alpha);
    const double area = integrateSphere([&](Vec3f m) { return d.D(m) * std::max(0.0f, m.z); });
    EXPECT_NEAR(area, 1, 1e-3) << "alpha " << alpha;
  }
}

// The area of the facets visible from v, projected on v, is the macro surface's projected
// area cos(theta_v) (Heitz 2014, "Understanding the Masking-Shadowing Function"). Exact
// for GGX's Smith G1; Beckmann's G1 is Walter's rational fit, good to about a percent.
TEST_P(MicrofacetDistributionTest, VisibleProjectedAreaIsCosine) {
  const float tolerance = GetParam() == MicrofacetType::GGX ? 1e-3f : 1.5e-2f;
  for (const float alpha : {0.2f, 0.6f}) {
    const MicrofacetDistribution d(GetParam(), alpha);
    for (const float cosV : {0.95f, 0.5f, 0.2f}) {
      const Vec3f v = directionFromCos(cosV);
      const double area =
          integrateSphere([&](Vec3f m) { return d.G1(v, m) * std::max(0.0f, dot(v, m)) * d.D(m); });
      EXPECT_NEAR(area / cosV, 1, tolerance) << "alpha " << alpha << " cos " << cosV;
    }
  }
}

// normalPdf is a density over facet normals: it integrates to one and sampleNormal only
// returns normals where it is positive.
TEST_P(MicrofacetDistributionTest, NormalPdfIsNormalizedAndMatchesSamples) {
  const MicrofacetDistribution d(GetParam(), 0.4f);
  Uniform rng(11);
  for (const float cosV : {0.9f, 0.3f}) {
    const Vec3f wo = directionFromCos(cosV);
    EXPECT_NEAR(integrateSphere([&](Vec3f m) { return d.normalPdf(wo, m); }), 1, 1e-3);
    for (int i = 0; i < 1000; ++i) {
      const Vec3f m = d.sampleNormal(wo, rng.next2());
      EXPECT_NEAR(length(m), 1, 1e-5f);
      EXPECT_GT(d.normalPdf(wo, m), 0);
    }
  }
}

TEST_P(MicrofacetDistributionTest, ShadowingIsAFraction) {
  const MicrofacetDistribution d(GetParam(), 0.5f);
  const Vec3f m = normalize(Vec3f{0.2f, 0.1f, 1});
  for (const float cosV : {1.0f, 0.5f, 0.05f}) {
    const float g = d.G1(directionFromCos(cosV), m);
    EXPECT_GE(g, 0);
    EXPECT_LE(g, 1);
  }
  EXPECT_NEAR(d.G1({0, 0, 1}, {0, 0, 1}), 1, 1e-6f);
  // A facet seen from behind shadows completely.
  EXPECT_EQ(d.G1(normalize(Vec3f{-1, 0, 0.1f}), normalize(Vec3f{1, 0, 0.5f})), 0);
  EXPECT_EQ(d.D({0, 0, -1}), 0);
}

INSTANTIATE_TEST_SUITE_P(Distributions, MicrofacetDistributionTest,
                         ::testing::Values(MicrofacetType::GGX, MicrofacetType::Beckmann),
                         [](const auto& info) {
                           return info.param == MicrofacetType::GGX ? "GGX" : "Beckmann";
                         });

TEST(GlossyLobeSymbol, Threshold) {
  EXPECT_EQ(glossyLobeSymbol(0.05f, 0.1f, LobeSymbol::T), LobeSymbol::T);
  EXPECT_EQ(glossyLobeSymbol(0.1f, 0.1f, LobeSymbol::R), LobeSymbol::D);
}

}  // namespace
}  // namespace pathfarm::bsdftest
