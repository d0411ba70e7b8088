// The lobe split of Bsdf (evalLobes and BsdfSample::lobe / lobeWeight) that the path-space
// decomposition routes throughput with: the parts add up to eval and weight, each part sits
// at the index of its lobe in lobes(), delta lobes get nothing from eval, and the parts are
// physically the right ones (plastic's base reflects rho (1 - F(wo)), glass reflects F).
// Also checks that the refactored rough plastic still produces the bits it always did.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "renderer/materials/bsdf.h"
#include "renderer/materials/fresnel.h"
#include "renderer/materials/microfacet.h"
#include "renderer/materials/plastic.h"
#include "renderer/math/sampling.h"
#include "tests/renderer/materials/bsdf_test_support.h"

namespace pathfarm::bsdftest {
namespace {

// Same value, NaN matching NaN: the split must reproduce eval even where eval degenerates.
bool sameFloat(float a, float b) { return a == b || (std::isnan(a) && std::isnan(b)); }
bool sameRgb(Rgb a, Rgb b) { return sameFloat(a.r, b.r) && sameFloat(a.g, b.g) && sameFloat(a.b, b.b); }
bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool sameBits(Rgb a, Rgb b) { return sameBits(a.r, b.r) && sameBits(a.g, b.g) && sameBits(a.b, b.b); }
bool sameBits(Vec3f a, Vec3f b) { return sameBits(a.x, b.x) && sameBits(a.y, b.y) && sameBits(a.z, b.z); }

// Uniform over the whole sphere, grazing directions included.
Vec3f anyDirection(Uniform& rng) { return sampleUniformSphere(rng.next2()); }

// Every configuration of bsdf_test.cpp (the colored non-delta ones and the white ones of
// the energy test, with the smooth metal and glass), plus glossy lobes sharp enough to count
// as R and T.
std::vector<MaterialCase> lobeCases() {
  using MT = MaterialType;
  using MF = MicrofacetType;
  std::vector<MaterialCase> cases = nonDeltaCases();
  for (MaterialCase c : nonDeltaCases()) {
    c.name = "White" + c.name;
    c.albedo = Rgb(1);
    c.material.useSpecularColor = true;
    cases.push_back(c);
  }
  Material whiteConductor = makeMaterial(MT::Conductor, MF::GGX, 0);
  whiteConductor.useSpecularColor = true;
  cases.push_back({"WhiteConductor", whiteConductor, Rgb(1), false});
  cases.push_back({"Conductor", makeMaterial(MT::Conductor, MF::GGX, 0), Rgb(1), false});
  cases.push_back({"Dielectric", makeMaterial(MT::Dielectric, MF::GGX, 0), Rgb(1), true});
  cases.push_back(
      {"RoughConductorComplexIor", makeMaterial(MT::RoughConductor, MF::GGX, 0.3f), Rgb(1), false});
  const Rgb albedo{0.8f, 0.5f, 0.2f};
  cases.push_back({"SharpRoughConductor", makeMaterial(MT::RoughConductor, MF::GGX, 0.05f), albedo, false});
  cases.push_back({"SharpRoughDielectric", makeMaterial(MT::RoughDielectric, MF::GGX, 0.05f), albedo, true});
  cases.push_back(
      {"SharpRoughPlasticBeckmann", makeMaterial(MT::RoughPlastic, MF::Beckmann, 0.05f), albedo, false});
  // All three lobes, glossy enough for R and T, and smooth (delta R and T beside D).
  cases.push_back({"SharpMetallicRoughness", metallicRoughness(0.05f, 0.5f, 0.5f), albedo, false});
  cases.push_back({"SmoothMetallicRoughness", metallicRoughness(0, 0.5f, 0.5f), albedo, false});
  return cases;
}

class BsdfLobeSplit : public ::testing::TestWithParam<MaterialCase> {};

// evalLobes sums to eval bit for bit (bsdf.h promises exactness), puts nothing on delta
// lobes or past lobes().count, and no part is negative.
TEST_P(BsdfLobeSplit, EvalLobesSumToEval) {
  const MaterialCase& c = GetParam();
  const Bsdf bsdf(c.material, c.albedo, kRoughnessThreshold);
  const LobeList lobes = bsdf.lobes();
  Uniform rng(21);
  int nonZero = 0;
  for (int i = 0; i < 40000; ++i) {
    // Half the pairs on the sides the material is meant for, half anywhere.
    const bool anywhere = i % 2 == 1;
    const Vec3f wo = anywhere ? anyDirection(rng) : randomDirection(rng, c.twoSided);
    const Vec3f wi = anywhere ? anyDirection(rng) : randomDirection(rng, true);
    const LobeValues v = bsdf.evalLobes(wo, wi);
    const Rgb f = bsdf.eval(wo, wi);
    ASSERT_TRUE(sameRgb(v.sum(), f)) << "wo.z " << wo.z << " wi.z " << wi.z << ": " << v.value[0].g << " + "
                                     << v.value[1].g << " + " << v.value[2].g << " vs " << f.g;
    nonZero += !f.isBlack();
    for (int k = 0; k < kMaxLobes; ++k) {
      if (k >= lobes.count || lobes.lobes[k].delta) {
        ASSERT_TRUE(v.value[k].isBlack()) << "lobe " << k;
      }
      for (int ch = 0; ch < 3; ++ch) ASSERT_GE(v.value[k][ch], 0) << "lobe " << k;
    }
  }
  if (bsdf.hasNonDeltaLobe()) {
    EXPECT_GT(nonZero, 5000);
  }
}

// Degenerate directions: the split still reproduces eval (NaN for NaN, if ever).
TEST_P(BsdfLobeSplit, EvalLobesSumToEvalAtDegenerateDirections) {
  const MaterialCase& c = GetParam();
  const Bsdf bsdf(c.material, c.albedo, kRoughnessThreshold);
  const Vec3f dirs[] = {{0, 0, 1}, {1, 0, 0}, {0, 0, -1}, {0, 0, 0}, {0.6f, 0.8f, 0}, {1e-7f, 0, 1}, {0, 0, 1e-30f}};
  for (const Vec3f wo : dirs) {
    for (const Vec3f wi : dirs) {
      const LobeValues v = bsdf.evalLobes(wo, wi);
      EXPECT_TRUE(sameRgb(v.sum(), bsdf.eval(wo, wi)));
    }
  }
}

// The sample's split: the lobe index names the sampled lobe (its symbol and delta flag),
// the parts add up to the weight, a delta sample gives everything to its lobe, and a
// non-delta sample's parts are evalLobes / pdf.
TEST_P(BsdfLobeSplit, SampleLobeWeightsSplitTheWeight) {
  const MaterialCase& c = GetParam();
  const Bsdf bsdf(c.material, c.albedo, kRoughnessThreshold);
  const LobeList lobes = bsdf.lobes();
  // Non-delta lobes that share directions: the rough plastic's coating and base, the
  // metallic-roughness material's reflection and diffuse base.
  const bool overlappingLobes =
      c.material.type == MaterialType::RoughPlastic || c.material.type == MaterialType::MetallicRoughness;
  Uniform rng(22);
  int samples = 0, perLobe[kMaxLobes] = {};
  for (int i = 0; i < 40000; ++i) {
    const Vec3f wo = i % 4 == 3 ? anyDirection(rng) : randomDirection(rng, c.twoSided);
    const float uLobe = rng.next();
    const auto s = bsdf.sample(wo, uLobe, rng.next2());
    if (!s) continue;
    ++samples;
    ASSERT_GE(s->lobe, 0);
    ASSERT_LT(s->lobe, lobes.count);
    ++perLobe[s->lobe];
    const Lobe& lobe = lobes.lobes[s->lobe];
    ASSERT_EQ(lobeSymbolChar(lobe.symbol), lobeSymbolChar(s->symbol));
    ASSERT_EQ(lobe.delta, s->delta);
    // Entries past the lobe count are zero.
    for (int k = lobes.count; k < kMaxLobes; ++k) ASSERT_TRUE(s->lobeWeight[k].isBlack());

    const Rgb sum = s->lobeWeight[0] + s->lobeWeight[1] + s->lobeWeight[2];
    if (s->delta) {
      ASSERT_TRUE(sameBits(s->lobeWeight[s->lobe], s->weight));
      for (int k = 0; k < kMaxLobes; ++k) {
        if (k != s->lobe) {
          ASSERT_TRUE(s->lobeWeight[k].isBlack()) << "lobe " << k;
        }
      }
      continue;
    }
    // A non-delta sample gives nothing to a delta lobe (the smooth plastic's coating).
    for (int k = 0; k < lobes.count; ++k) {
      if (lobes.lobes[k].delta) {
        ASSERT_TRUE(s->lobeWeight[k].isBlack()) << "delta lobe " << k;
      }
    }
    const LobeValues v = bsdf.evalLobes(wo, s->wi);
    const float pdf = bsdf.pdf(wo, s->wi);
    // Near the horizon sample() and eval / pdf may part by more than rounding (see below).
    const bool grazing = std::abs(wo.z) < 0.02f;
    for (int ch = 0; ch < 3; ++ch) {
      if (overlappingLobes) {
        // Each part rounded on its own (bsdf.h): within 6 * 2^-24 relative, so within 1e-6.
        ASSERT_LE(std::abs(sum[ch] - s->weight[ch]), 6.0001f * 0x1p-24f * s->weight[ch] + 1e-30f)
            << "channel " << ch << ": " << sum[ch] << " vs " << s->weight[ch];
        ASSERT_LE(std::abs(sum[ch] - s->weight[ch]), 1e-6f * s->weight[ch]);
      } else {
        ASSERT_EQ(sum[ch], s->weight[ch]) << "channel " << ch;
      }
      for (int k = 0; k < lobes.count; ++k) {
        // As SampleWeightIsEvalOverPdf: sample() may compute through the sampled facet
        // normal while eval and pdf recompute the half vector.
        if (!grazing) {
          ASSERT_TRUE(nearlyEqual(s->lobeWeight[k][ch], v.value[k][ch] / pdf, 2e-3f))
              << "lobe " << k << " channel " << ch << ": " << s->lobeWeight[k][ch] << " vs "
              << v.value[k][ch] / pdf;
        }
        if (overlappingLobes) {
          // Both evaluate exactly as evalLobes and pdf do: same bits.
          ASSERT_TRUE(sameBits(s->lobeWeight[k], v.value[k] / pdf)) << "lobe " << k;
        }
      }
    }
  }
  EXPECT_GT(samples, 10000);
  // Every lobe gets sampled.
  for (int k = 0; k < lobes.count; ++k) EXPECT_GT(perLobe[k], 0) << "lobe " << k;
}

INSTANTIATE_TEST_SUITE_P(Materials, BsdfLobeSplit, ::testing::ValuesIn(lobeCases()), caseName);

Material plastic(MaterialType type, MicrofacetType distribution, float alpha, float ior = 1.5f) {
  Material m = makeMaterial(type, distribution, alpha);
  m.ior = ior;
  return m;
}

// The plastic's base as plastic.h defines it, computed here independently.
Rgb plasticBase(Rgb rho, float ior, Vec3f wo, Vec3f wi) {
  const float fo = fresnelDielectric(wo.z, ior).reflectance, fi = fresnelDielectric(wi.z, ior).reflectance;
  const float fdrInt = fresnelDiffuseReflectance(1 / ior);
  return rho * ((1 - fo) * (1 - fi) * wi.z / (kPi * ior * ior * (1 - fdrInt)));
}

TEST(BsdfLobeRouting, PlasticLobesAreCoatingThenBase) {
  for (const MaterialType type : {MaterialType::Plastic, MaterialType::RoughPlastic}) {
    const LobeList lobes = Bsdf(plastic(type, MicrofacetType::GGX, 0.3f), Rgb(0.5f), kRoughnessThreshold).lobes();
    ASSERT_EQ(lobes.count, 2);
    EXPECT_EQ(lobes.lobes[1].symbol, LobeSymbol::D);
    EXPECT_FALSE(lobes.lobes[1].delta);
    EXPECT_EQ(lobes.lobes[0].delta, type == MaterialType::Plastic);
  }
}

// Plastic: nothing below the horizon on either lobe; the base part is the diffuse base
// formula (colored by rho), the coating part is colorless.
TEST(BsdfLobeRouting, PlasticBaseAndCoatingParts) {
  const Rgb rho{0.9f, 0.4f, 0.1f};
  Uniform rng(23);
  for (const MaterialType type : {MaterialType::Plastic, MaterialType::RoughPlastic}) {
    for (const MicrofacetType distribution : {MicrofacetType::GGX, MicrofacetType::Beckmann}) {
      const Material m = plastic(type, distribution, 0.3f, 1.7f);
      const Bsdf bsdf(m, rho, kRoughnessThreshold);
      for (int i = 0; i < 2000; ++i) {
        const Vec3f wo = randomDirection(rng, false), up = randomDirection(rng, false);
        const Vec3f down{up.x, up.y, -up.z};
        // wi below the horizon, and wo below it: both lobes zero.
        for (const LobeValues& v : {bsdf.evalLobes(wo, down), bsdf.evalLobes(down, up)}) {
          EXPECT_TRUE(v.value[0].isBlack());
          EXPECT_TRUE(v.value[1].isBlack());
        }
        const LobeValues v = bsdf.evalLobes(wo, up);
        const Rgb base = plasticBase(rho, m.ior, wo, up);
        for (int ch = 0; ch < 3; ++ch) {
          ASSERT_TRUE(nearlyEqual(v.value[1][ch], base[ch], 1e-5f)) << "channel " << ch;
        }
        EXPECT_GT(v.value[1].r, 0);
        EXPECT_EQ(v.value[0].r, v.value[0].g);
        EXPECT_EQ(v.value[0].r, v.value[0].b);
        if (type == MaterialType::Plastic) {
          EXPECT_TRUE(v.value[0].isBlack());
        }
      }
    }
  }
}

// Rough plastic: the coating's share is large at the mirror direction of a glossy coating
// and small far from it.
TEST(BsdfLobeRouting, RoughPlasticCoatingPeaksAtTheMirrorDirection) {
  const Material m = plastic(MaterialType::RoughPlastic, MicrofacetType::GGX, 0.05f);
  const Bsdf bsdf(m, Rgb(0.5f), kRoughnessThreshold);
  const Vec3f wo = directionFromCos(0.6f, 0.0f);
  const LobeValues mirror = bsdf.evalLobes(wo, {-wo.x, -wo.y, wo.z});
  EXPECT_GT(mirror.value[0].g, 10 * mirror.value[1].g);
  const LobeValues away = bsdf.evalLobes(wo, wo);  // back towards the viewer, 53 degrees off the mirror
  EXPECT_LT(away.value[0].g, 1e-2f * away.value[1].g);  // GGX tails are long, not zero
  EXPECT_GT(away.value[1].g, 0);
}

// Rough glass: reflection on the R lobe (index 0) when wi is on wo's side, refraction on the
// T lobe (index 1) otherwise, from outside and from inside.
TEST(BsdfLobeRouting, RoughDielectricReflectionAndRefractionParts) {
  for (const float alpha : {0.05f, 0.3f}) {
    const Material m = makeMaterial(MaterialType::RoughDielectric, MicrofacetType::GGX, alpha);
    const Bsdf bsdf(m, Rgb(1), kRoughnessThreshold);
    const LobeList lobes = bsdf.lobes();
    if (alpha < kRoughnessThreshold) {
      EXPECT_EQ(lobes.lobes[0].symbol, LobeSymbol::R);
      EXPECT_EQ(lobes.lobes[1].symbol, LobeSymbol::T);
    }
    Uniform rng(24);
    int reflected = 0, refracted = 0;
    for (int i = 0; i < 20000; ++i) {
      const Vec3f wo = randomDirection(rng, true), wi = randomDirection(rng, true);
      const LobeValues v = bsdf.evalLobes(wo, wi);
      const Rgb f = bsdf.eval(wo, wi);
      const bool sameSide = (wo.z > 0) == (wi.z > 0);
      EXPECT_TRUE(v.value[sameSide ? 1 : 0].isBlack());
      EXPECT_TRUE(v.value[sameSide ? 0 : 1] == f);
      (sameSide ? reflected : refracted) += !f.isBlack();

      const float uLobe = rng.next();
      const auto s = bsdf.sample(wo, uLobe, rng.next2());
      if (!s) continue;
      const int expectedLobe = (wo.z > 0) == (s->wi.z > 0) ? 0 : 1;
      EXPECT_EQ(s->lobe, expectedLobe);
      EXPECT_TRUE(s->lobeWeight[expectedLobe] == s->weight);
      EXPECT_TRUE(s->lobeWeight[1 - expectedLobe].isBlack());
    }
    EXPECT_GT(reflected, 1000);
    EXPECT_GT(refracted, 1000);
  }
}

// Smooth glass: reflection (including total internal reflection) is lobe 0, refraction 1.
TEST(BsdfLobeRouting, SmoothDielectricSampledLobes) {
  const Material m = makeMaterial(MaterialType::Dielectric, MicrofacetType::GGX, 0);
  const Bsdf bsdf(m, Rgb(1), kRoughnessThreshold);
  for (const float cosTheta : {0.9f, 0.3f, -0.9f, -0.5f /* past the critical angle */}) {
    const Vec3f wo = directionFromCos(cosTheta);
    for (const float uLobe : {0.0f, 0.99999994f}) {
      const auto s = bsdf.sample(wo, uLobe, {0.5f, 0.5f});
      ASSERT_TRUE(s);
      const bool reflected = s->wi.z * wo.z > 0;
      EXPECT_EQ(s->lobe, reflected ? 0 : 1);
      EXPECT_EQ(s->symbol, reflected ? LobeSymbol::R : LobeSymbol::T);
      EXPECT_TRUE(s->lobeWeight[s->lobe] == s->weight);
      EXPECT_TRUE(s->lobeWeight[1 - s->lobe].isBlack());
      const LobeValues v = bsdf.evalLobes(wo, s->wi);
      EXPECT_TRUE(v.value[0].isBlack() && v.value[1].isBlack());
    }
  }
}

struct LobeEstimate {
  double mean[2][3] = {}, stdError[2][3] = {};
};

// E[lobeWeight[k]] over n samples per lobe and channel, with standard errors.
LobeEstimate lobeAlbedo(const Bsdf& bsdf, Vec3f wo, int n, uint32_t seed) {
  Uniform rng(seed);
  double sum[2][3] = {}, sum2[2][3] = {};
  for (int i = 0; i < n; ++i) {
    const float uLobe = rng.next();
    const auto s = bsdf.sample(wo, uLobe, rng.next2());
    if (!s) continue;
    for (int k = 0; k < 2; ++k) {
      for (int ch = 0; ch < 3; ++ch) {
        const double w = s->lobeWeight[k][ch];
        sum[k][ch] += w;
        sum2[k][ch] += w * w;
      }
    }
  }
  LobeEstimate e;
  for (int k = 0; k < 2; ++k) {
    for (int ch = 0; ch < 3; ++ch) {
      e.mean[k][ch] = sum[k][ch] / n;
      e.stdError[k][ch] = std::sqrt(std::max(0.0, sum2[k][ch] / n - e.mean[k][ch] * e.mean[k][ch]) / n);
    }
  }
  return e;
}

// The physical check of the split: the rough plastic's base reflects rho (1 - F(wo)) in all
// (plastic.h), whichever lobe sampled the direction. White albedo, and a colored one that
// tells the base from the colorless coating.
TEST(BsdfLobeEnergy, RoughPlasticBaseAlbedoIsAttenuatedRho) {
  for (const MicrofacetType distribution : {MicrofacetType::GGX, MicrofacetType::Beckmann}) {
    for (const float alpha : {0.2f, 0.5f}) {
      for (const Rgb rho : {Rgb(1), Rgb(0.9f, 0.5f, 0.1f)}) {
        const Material m = plastic(MaterialType::RoughPlastic, distribution, alpha);
        const Bsdf bsdf(m, rho, kRoughnessThreshold);
        for (const float cosTheta : {0.9f, 0.5f, 0.15f}) {
          const Vec3f wo = directionFromCos(cosTheta);
          const float f = fresnelDielectric(cosTheta, m.ior).reflectance;
          const LobeEstimate e = lobeAlbedo(bsdf, wo, 200000, 25);
          for (int ch = 0; ch < 3; ++ch) {
            const double expected = rho[ch] * (1 - f);
            EXPECT_NEAR(e.mean[1][ch], expected, 3 * e.stdError[1][ch])
                << "alpha " << alpha << " cos " << cosTheta << " channel " << ch;
            // The coating is colorless, sample by sample: rho goes to the base alone.
            EXPECT_EQ(e.mean[0][ch], e.mean[0][0]);
          }
        }
      }
    }
  }
}

// Smooth plastic and smooth glass have closed forms for both lobes: the coating or mirror
// reflects F(wo), the base rho (1 - F(wo)), the refraction 1 - F(wo) in flux.
TEST(BsdfLobeEnergy, SmoothPlasticAndGlassLobeAlbedos) {
  const Rgb rho{1.0f, 0.6f, 0.1f};
  // Bsdf keeps a reference to its material.
  const Material plasticMaterial = plastic(MaterialType::Plastic, MicrofacetType::GGX, 0);
  const Material glassMaterial = makeMaterial(MaterialType::Dielectric, MicrofacetType::GGX, 0);
  const Bsdf plasticBsdf(plasticMaterial, rho, kRoughnessThreshold);
  const Bsdf glass(glassMaterial, Rgb(1), kRoughnessThreshold);
  for (const float cosTheta : {0.9f, 0.5f, 0.1f}) {
    const float f = fresnelDielectric(cosTheta, 1.5f).reflectance;
    const LobeEstimate p = lobeAlbedo(plasticBsdf, directionFromCos(cosTheta), 100000, 26);
    const LobeEstimate g = lobeAlbedo(glass, directionFromCos(cosTheta), 100000, 27);
    for (int ch = 0; ch < 3; ++ch) {
      EXPECT_NEAR(p.mean[0][ch], f, 3 * p.stdError[0][ch] + 1e-6) << "cos " << cosTheta;
      EXPECT_NEAR(p.mean[1][ch], rho[ch] * (1 - f), 3 * p.stdError[1][ch] + 1e-6) << "cos " << cosTheta;
      EXPECT_NEAR(g.mean[0][ch], f, 3 * g.stdError[0][ch] + 1e-6) << "cos " << cosTheta;
      EXPECT_NEAR(g.mean[1][ch] * 1.5 * 1.5, 1 - f, 3 * 1.5 * 1.5 * g.stdError[1][ch] + 1e-6)
          << "cos " << cosTheta;
    }
  }
}

// Bit-identity with the rough plastic as it was before eval and sample were rewritten on top
// of evalLobes: a verbatim copy of the old formulas, compared bit for bit (the renderer's
// images are compared bit for bit).
Rgb oldRoughPlasticEval(const PlasticBase& base, const MicrofacetDistribution& distribution, Vec3f wo, Vec3f wi) {
  if (wo.z <= 0 || wi.z <= 0) return {};
  const Vec3f m = normalize(wo + wi);
  const float coating = base.fresnel(dot(wo, m)) * distribution.reflectionEval(wo, wi, m);
  return Rgb(coating) + base.eval(wo, wi);
}

float oldRoughPlasticPdf(const PlasticBase& base, const MicrofacetDistribution& distribution, Vec3f wo, Vec3f wi) {
  if (wo.z <= 0 || wi.z <= 0) return 0;
  const float coating = base.coatingProbability(wo);
  return coating * distribution.reflectionPdf(wo, normalize(wo + wi)) + (1 - coating) * cosineHemispherePdf(wi.z);
}

std::optional<BsdfSample> oldRoughPlasticSample(const PlasticBase& base, const MicrofacetDistribution& distribution,
                                                LobeSymbol coatingSymbol, Vec3f wo, float uLobe, Vec2f u) {
  if (wo.z <= 0) return std::nullopt;
  Vec3f wi;
  LobeSymbol symbol;
  if (uLobe < base.coatingProbability(wo)) {
    const Vec3f m = distribution.sampleNormal(wo, u);
    if (dot(wo, m) <= 0) return std::nullopt;
    wi = reflect(wo, m);
    symbol = coatingSymbol;
  } else {
    wi = sampleCosineHemisphere(u);
    symbol = LobeSymbol::D;
  }
  if (wi.z <= 0) return std::nullopt;
  const float pdf = oldRoughPlasticPdf(base, distribution, wo, wi);
  BsdfSample s;
  s.wi = wi;
  s.weight = oldRoughPlasticEval(base, distribution, wo, wi) / pdf;
  s.pdf = pdf;
  s.symbol = symbol;
  return s;
}

TEST(BsdfLobeBitIdentity, RoughPlasticMatchesTheFormulasBeforeTheSplit) {
  Uniform rng(28);
  for (const MicrofacetType distribution : {MicrofacetType::GGX, MicrofacetType::Beckmann}) {
    for (const float alpha : {0.05f, 0.2f, 0.6f}) {
      for (const Rgb rho : {Rgb(1), Rgb(0.8f, 0.5f, 0.2f)}) {
        const Material m = plastic(MaterialType::RoughPlastic, distribution, alpha, 1.6f);
        const Bsdf bsdf(m, rho, kRoughnessThreshold);
        const PlasticBase base(rho, m.ior);
        const MicrofacetDistribution d(distribution, alpha);
        const LobeSymbol coatingSymbol = glossyLobeSymbol(alpha, kRoughnessThreshold, LobeSymbol::R);
        for (int i = 0; i < 20000; ++i) {
          const Vec3f wo = i % 2 ? anyDirection(rng) : randomDirection(rng, false);
          const Vec3f wi = i % 2 ? anyDirection(rng) : randomDirection(rng, false);
          ASSERT_TRUE(sameBits(bsdf.eval(wo, wi), oldRoughPlasticEval(base, d, wo, wi)));
          ASSERT_TRUE(sameBits(bsdf.pdf(wo, wi), oldRoughPlasticPdf(base, d, wo, wi)));
          const float uLobe = rng.next();
          const Vec2f u = rng.next2();
          const auto s = bsdf.sample(wo, uLobe, u);
          auto old = oldRoughPlasticSample(base, d, coatingSymbol, wo, uLobe, u);
          // Bsdf::sample's net for degenerate samples, as before.
          if (old && (!(old->pdf > 0) || !old->weight.isFinite() || !isFinite(old->wi))) old.reset();
          ASSERT_EQ(s.has_value(), old.has_value());
          if (!s) continue;
          ASSERT_TRUE(sameBits(s->wi, old->wi));
          ASSERT_TRUE(sameBits(s->weight, old->weight));
          ASSERT_TRUE(sameBits(s->pdf, old->pdf));
          ASSERT_EQ(s->symbol, old->symbol);
          ASSERT_FALSE(s->delta);
        }
      }
    }
  }
}

}  // namespace
}  // namespace pathfarm::bsdftest
