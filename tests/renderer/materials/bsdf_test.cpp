// Physical and statistical checks of every material through the Bsdf interface: sampling
// agrees with eval and pdf, pdfs are normalized, no energy is created, reflection is
// reciprocal, and lobes are classified as the light-path expressions need.
#include "renderer/materials/bsdf.h"

#include <gtest/gtest.h>

#include <cmath>

#include "renderer/materials/fresnel.h"
#include "tests/renderer/materials/bsdf_test_support.h"

namespace pathfarm::bsdftest {
namespace {

class BsdfNonDeltaMaterial : public ::testing::TestWithParam<MaterialCase> {};

// (1) Whatever sample() returns for a non-delta lobe must be reproducible by eval and pdf,
// or MIS weights computed from pdf() would be biased.
TEST_P(BsdfNonDeltaMaterial, SampleWeightIsEvalOverPdf) {
  const MaterialCase& c = GetParam();
  const Bsdf bsdf(c.material, c.albedo, kRoughnessThreshold);
  Uniform rng(1);
  int checked = 0;
  for (int i = 0; i < 20000; ++i) {
    const Vec3f wo = randomDirection(rng, c.twoSided);
    const float uLobe = rng.next();
    const auto s = bsdf.sample(wo, uLobe, rng.next2());
    if (!s || s->delta) continue;
    ++checked;
    const float pdf = bsdf.pdf(wo, s->wi);
    const Rgb f = bsdf.eval(wo, s->wi);
    ASSERT_TRUE(nearlyEqual(s->pdf, pdf, 2e-3f)) << "sample pdf " << s->pdf << " pdf() " << pdf;
    for (int ch = 0; ch < 3; ++ch) {
      ASSERT_TRUE(nearlyEqual(s->weight[ch], f[ch] / pdf, 2e-3f))
          << "channel " << ch << ": weight " << s->weight[ch] << " eval/pdf " << f[ch] / pdf;
    }
  }
  EXPECT_GT(checked, 5000);
}

// (1) pdf() is a density of the sampling procedure: over the sphere it integrates to the
// probability that sample() returns a non-delta direction.
TEST_P(BsdfNonDeltaMaterial, PdfIntegratesToNonDeltaSampleProbability) {
  const MaterialCase& c = GetParam();
  const Bsdf bsdf(c.material, c.albedo, kRoughnessThreshold);
  for (const Vec3f wo : testDirections(c.twoSided)) {
    const double integral = integrateSphere([&](Vec3f wi) { return bsdf.pdf(wo, wi); });
    Uniform rng(2);
    const int n = 100000;
    int nonDelta = 0;
    for (int i = 0; i < n; ++i) {
      const float uLobe = rng.next();
      const auto s = bsdf.sample(wo, uLobe, rng.next2());
      nonDelta += s && !s->delta;
    }
    const double p = double(nonDelta) / n;
    const double stdError = std::sqrt(p * (1 - p) / n);
    EXPECT_NEAR(integral, p, 3 * stdError + 1e-3) << "wo.z = " << wo.z;
    EXPECT_LE(integral, 1.001) << "wo.z = " << wo.z;
  }
}

// (3) Reflection is reciprocal: f(wo, wi) = f(wi, wo), i.e. eval / cos(wi) is symmetric.
// Rough glass refraction obeys the generalized form f(wo, wi) / n(wo)^2 = f(wi, wo) / n(wi)^2.
TEST_P(BsdfNonDeltaMaterial, Reciprocity) {
  const MaterialCase& c = GetParam();
  const Bsdf bsdf(c.material, c.albedo, kRoughnessThreshold);
  Uniform rng(3);
  for (int i = 0; i < 5000; ++i) {
    const Vec3f wo = randomDirection(rng, false);
    const Vec3f wi = randomDirection(rng, c.twoSided);
    // n^2 of each direction's medium; 1 above the surface.
    const float n2o = 1, n2i = wi.z > 0 ? 1 : c.material.ior * c.material.ior;
    const Rgb forward = bsdf.eval(wo, wi) / (std::abs(wi.z) * n2o);
    const Rgb backward = bsdf.eval(wi, wo) / (std::abs(wo.z) * n2i);
    for (int ch = 0; ch < 3; ++ch) {
      // The absolute slack covers refraction near the critical angle, where 1 - F is
      // ill-conditioned in float and tiny.
      ASSERT_TRUE(nearlyEqual(forward[ch], backward[ch], 1e-3f) ||
                  std::abs(forward[ch] - backward[ch]) < 1e-5f)
          << "wo.z " << wo.z << " wi.z " << wi.z << ": " << forward[ch] << " vs " << backward[ch];
    }
  }
}

// Never NaN or infinite, whatever the directions and random numbers.
TEST_P(BsdfNonDeltaMaterial, DegenerateInputsStayFinite) {
  const MaterialCase& c = GetParam();
  const Bsdf bsdf(c.material, c.albedo, kRoughnessThreshold);
  const Vec3f dirs[] = {{0, 0, 1}, {1, 0, 0}, {0, 0, -1}, {0, 0, 0}, {0.6f, 0.8f, 0}, {1e-7f, 0, 1}};
  const Vec2f us[] = {{0, 0}, {0.99999994f, 0.99999994f}, {0.5f, 0}, {0, 0.5f}};
  for (const Vec3f wo : dirs) {
    for (const Vec3f wi : dirs) {
      EXPECT_TRUE(bsdf.eval(wo, wi).isFinite());
      EXPECT_TRUE(std::isfinite(bsdf.pdf(wo, wi)));
    }
    for (const Vec2f u : us) {
      for (const float uLobe : {0.0f, 0.5f, 0.99999994f}) {
        const auto s = bsdf.sample(wo, uLobe, u);
        if (!s) continue;
        EXPECT_TRUE(s->weight.isFinite());
        EXPECT_TRUE(isFinite(s->wi));
        EXPECT_GT(s->pdf, 0);
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Materials, BsdfNonDeltaMaterial, ::testing::ValuesIn(nonDeltaCases()), caseName);

// (2) Energy: with white parameters no material reflects (plus transmits, in flux) more
// than it receives.
class BsdfWhiteMaterial : public ::testing::TestWithParam<MaterialCase> {};

TEST_P(BsdfWhiteMaterial, DirectionalAlbedoAtMostOne) {
  const MaterialCase& c = GetParam();
  for (const Vec3f wo : testDirections(c.twoSided)) {
    const Estimate e = directionalAlbedo(c.material, c.albedo, wo, 100000, 4);
    for (int ch = 0; ch < 3; ++ch) {
      EXPECT_LE(e.mean[ch], 1 + 3 * e.stdError[ch] + 1e-5f) << "wo.z = " << wo.z;
      EXPECT_GT(e.mean[ch], 0.3f) << "wo.z = " << wo.z;  // and it does not lose most of it
    }
  }
}

std::vector<MaterialCase> whiteCases() {
  using MT = MaterialType;
  using MF = MicrofacetType;
  std::vector<MaterialCase> cases = nonDeltaCases();
  for (MaterialCase& c : cases) c.albedo = Rgb(1);
  cases.push_back({"Conductor", makeMaterial(MT::Conductor, MF::GGX, 0), Rgb(1), false});
  cases.push_back({"Dielectric", makeMaterial(MT::Dielectric, MF::GGX, 0), Rgb(1), true});
  for (MaterialCase& c : cases) c.material.useSpecularColor = true;  // Schlick, f0 = 1: white metal
  // The physical gold-like default, still bounded by one.
  cases.push_back(
      {"RoughConductorComplexIor", makeMaterial(MT::RoughConductor, MF::GGX, 0.3f), Rgb(1), false});
  return cases;
}

INSTANTIATE_TEST_SUITE_P(Materials, BsdfWhiteMaterial, ::testing::ValuesIn(whiteCases()), caseName);

TEST(BsdfEnergy, DiffuseAlbedoIsReflectance) {
  const Rgb rho{0.8f, 0.5f, 0.2f};
  const Estimate e = directionalAlbedo(Material{}, rho, directionFromCos(0.4f), 20000, 5);
  for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(e.mean[ch], rho[ch], 3 * e.stdError[ch] + 1e-5f);
}

// Mitsuba's linear plastic model reflects exactly F(wo) + rho (1 - F(wo)); this checks the
// diffuse normalization by the internal diffuse Fresnel reflectance.
TEST(BsdfEnergy, SmoothPlasticAlbedoIsCoatingPlusAttenuatedBase) {
  Material m;
  m.type = MaterialType::Plastic;
  const Rgb rho{1.0f, 0.6f, 0.1f};
  for (const float ior : {1.5f, 1.9f}) {
    m.ior = ior;
    for (const float cosTheta : {0.9f, 0.5f, 0.1f}) {
      const float f = fresnelDielectric(cosTheta, ior).reflectance;
      const Estimate e = directionalAlbedo(m, rho, directionFromCos(cosTheta), 100000, 6);
      for (int ch = 0; ch < 3; ++ch) {
        EXPECT_NEAR(e.mean[ch], f + rho[ch] * (1 - f), 3 * e.stdError[ch] + 2e-3f)
            << "ior " << ior << " cos " << cosTheta << " channel " << ch;
      }
    }
  }
}

// A nearly smooth microfacet surface loses almost nothing to shadowing: the microfacet
// normalization (D, G, the 1/4 Jacobian, and the 1/eta^2 of refraction) is complete.
TEST(BsdfEnergy, NearlySmoothMicrofacetsConserveEnergy) {
  for (const MicrofacetType distribution : {MicrofacetType::GGX, MicrofacetType::Beckmann}) {
    for (const MaterialType type : {MaterialType::RoughConductor, MaterialType::RoughDielectric}) {
      Material m = makeMaterial(type, distribution, 0.05f);
      m.useSpecularColor = true;
      for (const float cosTheta : {0.9f, 0.5f, -0.9f}) {
        if (type == MaterialType::RoughConductor && cosTheta < 0) continue;
        const Estimate e = directionalAlbedo(m, Rgb(1), directionFromCos(cosTheta), 50000, 7);
        EXPECT_NEAR(e.mean.g, 1.0f, 0.02f) << materialTypeName(type) << " cos " << cosTheta;
      }
    }
  }
}

TEST(BsdfEnergy, SmoothConductorWithWhiteSpecularColorReflectsEverything) {
  Material m;
  m.type = MaterialType::Conductor;
  m.useSpecularColor = true;
  m.specularColor = Rgb(1);
  const Bsdf bsdf(m, Rgb(1), kRoughnessThreshold);
  for (const float cosTheta : {1.0f, 0.5f, 0.05f}) {
    const Vec3f wo = directionFromCos(cosTheta);
    const auto s = bsdf.sample(wo, 0.3f, {0.2f, 0.7f});
    ASSERT_TRUE(s);
    EXPECT_TRUE(s->delta);
    EXPECT_EQ(s->symbol, LobeSymbol::R);
    EXPECT_FLOAT_EQ(s->pdf, 1);
    EXPECT_FLOAT_EQ(s->weight.r, 1);
    EXPECT_FLOAT_EQ(s->wi.z, wo.z);
    EXPECT_FLOAT_EQ(s->wi.x, -wo.x);
  }
}

TEST(BsdfEnergy, SmoothConductorWeightIsConductorFresnel) {
  Material m;
  m.type = MaterialType::Conductor;
  const Bsdf bsdf(m, Rgb(1), kRoughnessThreshold);
  const auto s = bsdf.sample(directionFromCos(0.6f), 0.5f, {0.5f, 0.5f});
  ASSERT_TRUE(s);
  const Rgb f = fresnelConductor(0.6f, m.eta, m.k);
  EXPECT_FLOAT_EQ(s->weight.r, f.r);
  EXPECT_FLOAT_EQ(s->weight.b, f.b);
}

// Smooth glass: reflection is chosen with probability F and refraction with 1 - F; the
// reflected and transmitted fluxes (undoing the 1/eta^2 radiance scaling) add up to one.
TEST(BsdfEnergy, SmoothDielectricReflectancePlusTransmittanceIsOne) {
  Material m;
  m.type = MaterialType::Dielectric;
  m.ior = 1.5f;
  const Bsdf bsdf(m, Rgb(1), kRoughnessThreshold);
  for (const float cosTheta : {0.95f, 0.6f, 0.2f, -0.95f, -0.8f}) {
    const Vec3f wo = directionFromCos(cosTheta);
    const float eta = refractionEta(m, wo);
    const float expectedF = fresnelDielectric(std::abs(cosTheta), eta).reflectance;
    const auto r = bsdf.sample(wo, 0.0f, {0.5f, 0.5f});
    const auto t = bsdf.sample(wo, 0.99999994f, {0.5f, 0.5f});
    ASSERT_TRUE(r && t);
    EXPECT_EQ(r->symbol, LobeSymbol::R);
    EXPECT_EQ(t->symbol, LobeSymbol::T);
    EXPECT_TRUE(r->delta && t->delta);
    EXPECT_NEAR(r->pdf, expectedF, 1e-6f);
    EXPECT_NEAR(t->pdf, 1 - expectedF, 1e-6f);
    EXPECT_FLOAT_EQ(r->wi.z, wo.z);
    EXPECT_LT(t->wi.z * wo.z, 0);
    // Snell: sin_t = sin_i / eta, on the same side of the normal plane.
    EXPECT_NEAR(std::sqrt(1 - t->wi.z * t->wi.z), std::sqrt(1 - wo.z * wo.z) / eta, 1e-5f);
    EXPECT_LT(t->wi.x * wo.x, 0);
    const float reflected = r->weight.g * r->pdf;
    const float transmitted = t->weight.g * t->pdf * eta * eta;
    EXPECT_NEAR(reflected, expectedF, 1e-6f);
    EXPECT_NEAR(reflected + transmitted, 1.0f, 1e-5f) << "cos " << cosTheta;
    EXPECT_TRUE(bsdf.eval(wo, t->wi).isBlack());
    EXPECT_EQ(bsdf.pdf(wo, t->wi), 0);
  }
}

TEST(BsdfEnergy, SmoothDielectricTotalInternalReflection) {
  Material m;
  m.type = MaterialType::Dielectric;
  m.ior = 1.5f;
  const Bsdf bsdf(m, Rgb(1), kRoughnessThreshold);
  // From inside at 60 degrees, past the critical angle asin(1 / 1.5) = 41.8 degrees.
  const Vec3f wo = directionFromCos(-0.5f);
  const auto s = bsdf.sample(wo, 0.99999994f, {0.5f, 0.5f});
  ASSERT_TRUE(s);
  EXPECT_EQ(s->symbol, LobeSymbol::R);
  EXPECT_FLOAT_EQ(s->pdf, 1);
  EXPECT_FLOAT_EQ(s->weight.g, 1);
  EXPECT_FLOAT_EQ(s->wi.z, wo.z);
}

// (5) Lobe classification for light-path expressions.
LobeList lobesOf(MaterialType type, float alpha, float threshold = kRoughnessThreshold) {
  return Bsdf(makeMaterial(type, MicrofacetType::GGX, alpha), Rgb(0.5f), threshold).lobes();
}

void expectLobes(const LobeList& list, std::initializer_list<Lobe> expected) {
  ASSERT_EQ(list.count, int(expected.size()));
  int i = 0;
  for (const Lobe& lobe : expected) {
    EXPECT_EQ(lobeSymbolChar(list.lobes[i].symbol), lobeSymbolChar(lobe.symbol)) << "lobe " << i;
    EXPECT_EQ(list.lobes[i].delta, lobe.delta) << "lobe " << i;
    ++i;
  }
}

TEST(BsdfLobes, EachMaterialReportsItsLobes) {
  using MT = MaterialType;
  using S = LobeSymbol;
  expectLobes(lobesOf(MT::Diffuse, 0), {{S::D, false}});
  expectLobes(lobesOf(MT::Conductor, 0), {{S::R, true}});
  expectLobes(lobesOf(MT::RoughConductor, 0.05f), {{S::R, false}});
  expectLobes(lobesOf(MT::RoughConductor, 0.3f), {{S::D, false}});
  expectLobes(lobesOf(MT::Dielectric, 0), {{S::R, true}, {S::T, true}});
  expectLobes(lobesOf(MT::RoughDielectric, 0.05f), {{S::R, false}, {S::T, false}});
  expectLobes(lobesOf(MT::RoughDielectric, 0.3f), {{S::D, false}, {S::D, false}});
  expectLobes(lobesOf(MT::Plastic, 0), {{S::R, true}, {S::D, false}});
  expectLobes(lobesOf(MT::RoughPlastic, 0.05f), {{S::R, false}, {S::D, false}});
  expectLobes(lobesOf(MT::RoughPlastic, 0.3f), {{S::D, false}, {S::D, false}});
  // The threshold is the scene's, not a constant.
  expectLobes(lobesOf(MT::RoughConductor, 0.3f, 0.5f), {{S::R, false}});
}

TEST(BsdfLobes, SampledSymbolsMatchTheThreshold) {
  Uniform rng(8);
  for (const float alpha : {0.05f, 0.3f}) {
    const Material m = makeMaterial(MaterialType::RoughDielectric, MicrofacetType::GGX, alpha);
    const Bsdf bsdf(m, Rgb(1), kRoughnessThreshold);
    bool sawReflection = false, sawTransmission = false;
    for (int i = 0; i < 200; ++i) {
      const float uLobe = rng.next();
      const auto s = bsdf.sample(directionFromCos(0.3f), uLobe, rng.next2());
      if (!s) continue;
      const bool transmitted = s->wi.z < 0;
      (transmitted ? sawTransmission : sawReflection) = true;
      const LobeSymbol sharp = transmitted ? LobeSymbol::T : LobeSymbol::R;
      EXPECT_EQ(s->symbol, alpha < kRoughnessThreshold ? sharp : LobeSymbol::D);
      EXPECT_FALSE(s->delta);
    }
    EXPECT_TRUE(sawReflection && sawTransmission);
  }
}

TEST(BsdfLobes, HasNonDeltaLobe) {
  using MT = MaterialType;
  EXPECT_FALSE(Bsdf(makeMaterial(MT::Conductor, MicrofacetType::GGX, 0), Rgb(1), 0.1f).hasNonDeltaLobe());
  EXPECT_FALSE(Bsdf(makeMaterial(MT::Dielectric, MicrofacetType::GGX, 0), Rgb(1), 0.1f).hasNonDeltaLobe());
  for (const MT type :
       {MT::Diffuse, MT::RoughConductor, MT::RoughDielectric, MT::Plastic, MT::RoughPlastic}) {
    EXPECT_TRUE(Bsdf(makeMaterial(type, MicrofacetType::GGX, 0.2f), Rgb(1), 0.1f).hasNonDeltaLobe())
        << materialTypeName(type);
  }
}

TEST(BsdfLobes, Names) {
  EXPECT_EQ(lobeSymbolChar(LobeSymbol::D), 'D');
  EXPECT_EQ(lobeSymbolChar(LobeSymbol::R), 'R');
  EXPECT_EQ(lobeSymbolChar(LobeSymbol::T), 'T');
  // As the scene format spells them.
  EXPECT_EQ(materialTypeName(MaterialType::Diffuse), "diffuse");
  EXPECT_EQ(materialTypeName(MaterialType::Conductor), "conductor");
  EXPECT_EQ(materialTypeName(MaterialType::RoughConductor), "rough_conductor");
  EXPECT_EQ(materialTypeName(MaterialType::Dielectric), "dielectric");
  EXPECT_EQ(materialTypeName(MaterialType::RoughDielectric), "rough_dielectric");
  EXPECT_EQ(materialTypeName(MaterialType::Plastic), "plastic");
  EXPECT_EQ(materialTypeName(MaterialType::RoughPlastic), "rough_plastic");
}

}  // namespace
}  // namespace pathfarm::bsdftest
