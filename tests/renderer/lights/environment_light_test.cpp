// The environment light on its own: the map's orientation pinned by hand-derived
// directions, pdf() a density over the sphere, sample() distributed as pdf() says
// (chi-square), the mean radiance in closed form, the constant environment sampled
// exactly as before maps existed, and importance sampling's variance against uniform
// sampling's on a sky with a small sun.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "renderer/lights/environment_light.h"
#include "renderer/math/sampling.h"
#include "tests/renderer/sky_map.h"

namespace pathfarm {
namespace {

using test_support::skyMapTexels;

Vec3f normalized(float x, float y, float z) { return normalize(Vec3f{x, y, z}); }

// A map whose red channel is u at each texel's centre and green is v: bilinear lookups of
// a linear ramp return (u, v) of the direction itself, away from the seam and the poles.
EnvironmentLight rampMap(float rotationDegrees) {
  const int w = 64, h = 32;
  std::vector<Rgb> texels;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) texels.emplace_back((x + 0.5f) / w, (y + 0.5f) / h, 1.0f);
  return EnvironmentLight(w, h, texels, 1, rotationDegrees);
}

TEST(EnvironmentLight, MapOrientationFollowsTheDocumentedConvention) {
  const EnvironmentLight map = rampMap(0);
  struct Case {
    Vec3f direction;
    float u, v;
  };
  // Centre of the image: +x; three quarters across: +z; one quarter: -z; top row +y.
  for (const Case& c : {Case{{1, 0, 0}, 0.5f, 0.5f}, Case{{0, 0, 1}, 0.75f, 0.5f}, Case{{0, 0, -1}, 0.25f, 0.5f},
                        Case{normalized(1, 1, 0), 0.5f, 0.25f}, Case{normalized(0, -1, 1), 0.75f, 0.75f},
                        Case{normalized(1, 0, 1), 0.625f, 0.5f}}) {
    const Rgb r = map.radiance(c.direction);
    EXPECT_NEAR(r.r, c.u, 1e-5f) << c.direction.x << " " << c.direction.y << " " << c.direction.z;
    EXPECT_NEAR(r.g, c.v, 1e-5f) << c.direction.x << " " << c.direction.y << " " << c.direction.z;
  }
  // 90 degrees about +y turns the centre to -z, and +x to where -z was.
  const EnvironmentLight turned = rampMap(90);
  EXPECT_NEAR(turned.radiance({0, 0, -1}).r, 0.5f, 1e-5f);
  EXPECT_NEAR(turned.radiance({1, 0, 0}).r, 0.75f, 1e-5f);
  EXPECT_NEAR(turned.radiance({-1, 0, 0}).r, 0.25f, 1e-5f);
}

// One bright texel on a black map, right of the centre in the upper half of a 4x2 map:
// its centre is at u = 5/8, v = 1/4, the direction (1/2, 1/sqrt(2), 1/2). Lookups there
// read it in full, and most samples land in its quadrant x, y, z > 0.
TEST(EnvironmentLight, OneBrightTexelIsSeenAndSampledWhereTheConventionSays) {
  std::vector<Rgb> texels(8, Rgb(0));
  texels[2] = Rgb(8);
  const EnvironmentLight map(4, 2, texels, 1, 0);
  EXPECT_NEAR(map.radiance(normalized(0.5f, std::sqrt(0.5f), 0.5f)).r, 8, 1e-4f);
  EXPECT_NEAR(map.radiance(normalized(0.5f, std::sqrt(0.5f), -0.5f)).r, 0, 1e-4f);  // mirrored in z
  EXPECT_NEAR(map.radiance(normalized(0.5f, -std::sqrt(0.5f), 0.5f)).r, 0, 1e-4f);  // mirrored in y
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> uniform(0, 1);
  double towardsTexel = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const auto s = map.sample({uniform(rng), uniform(rng)});
    ASSERT_TRUE(s);
    if (s->direction.x > 0 && s->direction.y > 0 && s->direction.z > 0) ++towardsTexel;
  }
  // The bilinear spill gives the texel's own footprint 3/4 (across) x 7/8 (down, the row
  // clamped at the pole) = 21/32 of the sampling weight, all inside that quadrant.
  EXPECT_GT(towardsTexel / n, 9.0 / 16);
}

TEST(EnvironmentLight, RotationTurnsSamplesWithTheMap) {
  std::vector<Rgb> texels(8, Rgb(0));
  texels[2] = Rgb(8);
  const EnvironmentLight turned(4, 2, texels, 1, 90);
  // Turned 90 degrees about +y, (1/2, ., 1/2) goes to (1/2, ., -1/2).
  EXPECT_NEAR(turned.radiance(normalized(0.5f, std::sqrt(0.5f), -0.5f)).r, 8, 1e-4f);
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> uniform(0, 1);
  int inQuadrant = 0;
  for (int i = 0; i < 1000; ++i) {
    const auto s = turned.sample({uniform(rng), uniform(rng)});
    inQuadrant += s && s->direction.x > 0 && s->direction.z < 0;
  }
  EXPECT_GT(inQuadrant, 1000 * 9 / 16);
}

// A map for the density tests: smooth variation, a bright spot, a black band, turned by
// an angle that puts no texel edge on the test's grid.
EnvironmentLight textureMap() {
  const auto texels = skyMapTexels(48, 24, [](Vec3f d) {
    const float spot = dot(d, normalize(Vec3f{0.3f, 0.6f, -0.7f})) > 0.95f ? 40.0f : 0.0f;
    const float band = std::abs(d.y + 0.3f) < 0.1f ? 0.0f : 1.0f;
    return Rgb(band * (0.5f + 0.4f * d.x) + spot, band * (1 + d.z * d.z) + spot, 0.2f + spot);
  });
  return EnvironmentLight(48, 24, texels, 1.5f, 37);
}

// The integral of pdf() over cell (i, j) of a theta x phi grid (theta from +y, phi from
// +x towards +z), by a midpoint rule fine against the texels.
constexpr int kThetaBins = 18, kPhiBins = 36, kSub = 24;
double cellIntegral(const EnvironmentLight& light, int i, int j) {
  double sum = 0;
  const double dTheta = M_PI / kThetaBins / kSub, dPhi = 2 * M_PI / kPhiBins / kSub;
  for (int a = 0; a < kSub; ++a) {
    const double theta = M_PI * i / kThetaBins + (a + 0.5) * dTheta;
    for (int b = 0; b < kSub; ++b) {
      const double phi = 2 * M_PI * j / kPhiBins + (b + 0.5) * dPhi;
      const Vec3f d{static_cast<float>(std::sin(theta) * std::cos(phi)), static_cast<float>(std::cos(theta)),
                    static_cast<float>(std::sin(theta) * std::sin(phi))};
      sum += light.pdf(d) * std::sin(theta) * dTheta * dPhi;
    }
  }
  return sum;
}

int cellOf(Vec3f d) {
  const double theta = std::acos(std::clamp(static_cast<double>(d.y), -1.0, 1.0));
  double phi = std::atan2(d.z, d.x);
  if (phi < 0) phi += 2 * M_PI;
  const int i = std::min(kThetaBins - 1, static_cast<int>(theta / M_PI * kThetaBins));
  const int j = std::min(kPhiBins - 1, static_cast<int>(phi / (2 * M_PI) * kPhiBins));
  return i * kPhiBins + j;
}

TEST(EnvironmentLight, PdfIntegratesToOneOverTheSphere) {
  const EnvironmentLight light = textureMap();
  double total = 0;
  for (int i = 0; i < kThetaBins; ++i)
    for (int j = 0; j < kPhiBins; ++j) total += cellIntegral(light, i, j);
  EXPECT_NEAR(total, 1.0, 2e-3);
}

// Wilson and Hilferty 1931, as in bsdf_chi2_test.cpp.
double chiSquareQuantile(int dof, double normalQuantile) {
  const double v = 2.0 / (9.0 * dof);
  const double c = 1 - v + normalQuantile * std::sqrt(v);
  return dof * c * c * c;
}

TEST(EnvironmentLight, SamplesAreDistributedAsPdfSays) {
  const EnvironmentLight light = textureMap();
  const int n = 200000;
  std::vector<double> observed(kThetaBins * kPhiBins, 0), expected(observed.size(), 0);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> uniform(0, 1);
  int disagreements = 0;
  for (int k = 0; k < n; ++k) {
    const auto s = light.sample({uniform(rng), uniform(rng)});
    ASSERT_TRUE(s);
    // The density reported with a sample is pdf() of its direction, but for directions
    // that rounding moves across a texel edge.
    disagreements += std::abs(s->pdf - light.pdf(s->direction)) > 1e-3f * s->pdf;
    observed[static_cast<size_t>(cellOf(s->direction))] += 1;
  }
  EXPECT_LT(disagreements, n / 10000);
  for (int i = 0; i < kThetaBins; ++i)
    for (int j = 0; j < kPhiBins; ++j) expected[static_cast<size_t>(i * kPhiBins + j)] = n * cellIntegral(light, i, j);
  double chi2 = 0, pooledObserved = 0, pooledExpected = 0;
  int cells = 0;
  for (size_t k = 0; k < observed.size(); ++k) {
    if (expected[k] < 5) {
      pooledObserved += observed[k];
      pooledExpected += expected[k];
      continue;
    }
    chi2 += (observed[k] - expected[k]) * (observed[k] - expected[k]) / expected[k];
    ++cells;
  }
  // The black band's cells: pdf() says almost nothing lands there, and nothing must.
  EXPECT_LT(pooledObserved, pooledExpected + 5 * std::sqrt(pooledExpected) + 5);
  EXPECT_LT(chi2, chiSquareQuantile(cells - 1, 3.719)) << cells - 1 << " dof";
}

TEST(EnvironmentLight, MeanLuminanceOfAHemisphereSkyIsTheMeanOfItsHalves) {
  // The rows' solid angles add up to 2 pi on each side of the horizon.
  const EnvironmentLight sky(16, 8, test_support::hemisphereSkyTexels(16, 8, Rgb(1, 2, 3), Rgb(4)), 2, 10);
  EXPECT_NEAR(sky.meanLuminance(), 2 * (Rgb(1, 2, 3).luminance() + Rgb(4).luminance()) / 2, 1e-5);
  EXPECT_FALSE(sky.isBlack());
  EXPECT_TRUE(EnvironmentLight(16, 8, std::vector<Rgb>(128, Rgb(1)), 0, 0).isBlack());
  EXPECT_TRUE(EnvironmentLight().isBlack());
}

TEST(EnvironmentLight, ConstantSkySamplesTheSphereUniformlyAsBefore) {
  const EnvironmentLight sky(Rgb(0.5f, 1, 2));
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> uniform(0, 1);
  for (int i = 0; i < 100; ++i) {
    const Vec2f u{uniform(rng), uniform(rng)};
    const auto s = sky.sample(u);
    ASSERT_TRUE(s);
    const Vec3f expected = sampleUniformSphere(u);
    EXPECT_EQ(s->direction.x, expected.x);
    EXPECT_EQ(s->direction.y, expected.y);
    EXPECT_EQ(s->direction.z, expected.z);
    EXPECT_EQ(s->pdf, kUniformSpherePdf);
    EXPECT_EQ(sky.pdf(s->direction), kUniformSpherePdf);
    EXPECT_EQ(s->radiance.b, 2.0f);
  }
  EXPECT_EQ(sky.meanLuminance(), Rgb(0.5f, 1, 2).luminance());
}

TEST(EnvironmentLight, RejectsNegativeAndNonFiniteTexels) {
  EXPECT_THROW(EnvironmentLight(2, 1, {Rgb(1), Rgb(-1)}, 1, 0), std::invalid_argument);
  EXPECT_THROW(EnvironmentLight(2, 1, {Rgb(1), Rgb(NAN)}, 1, 0), std::invalid_argument);
  EXPECT_THROW(EnvironmentLight(2, 2, {Rgb(1), Rgb(1)}, 1, 0), std::invalid_argument);
}

// Irradiance at an upward-facing point, E = integral of L max(0, y) over directions, under
// a sky of 0.2 with a sun of radiance 2000 covering 2 pi (1 - 0.99965) = 0.0022 sr at 62
// degrees elevation (E about 3.9 from the sun, 0.6 from the sky). Uniform sampling's
// variance is about E_sun^2 4 pi / 0.0022, some 5700 E_sun^2. Sampling in proportion to
// luminance sin(theta) makes L / pdf nearly constant, leaving the cosine's variation and
// the sky's share: under E^2. Asking for a factor of 100 leaves a wide margin on both sides.
TEST(EnvironmentLight, ImportanceSamplingASunBeatsUniformSampling) {
  const Vec3f sun = normalize(Vec3f{0.5f, 1.2f, -0.4f});
  const int w = 512, h = 256;
  const auto texels = skyMapTexels(w, h, [&](Vec3f d) { return dot(d, sun) > 0.99965f ? Rgb(2000) : Rgb(0.2f); });
  const EnvironmentLight sky(w, h, texels, 1, 0);
  const int n = 40000;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> uniform(0, 1);
  double sum[2] = {}, squares[2] = {};
  for (int i = 0; i < n; ++i) {
    const Vec2f u{uniform(rng), uniform(rng)};
    const auto s = sky.sample(u);
    const double importance = s ? s->radiance.g * std::max(0.0f, s->direction.y) / s->pdf : 0;
    const Vec3f d = sampleUniformSphere({uniform(rng), uniform(rng)});
    const double uniformEstimate = sky.radiance(d).g * std::max(0.0f, d.y) / kUniformSpherePdf;
    for (const auto& [k, x] : {std::pair{0, importance}, std::pair{1, uniformEstimate}}) {
      sum[k] += x;
      squares[k] += x * x;
    }
  }
  double mean[2], variance[2];
  for (int k = 0; k < 2; ++k) {
    mean[k] = sum[k] / n;
    variance[k] = (squares[k] - n * mean[k] * mean[k]) / (n - 1);
  }
  // Both estimate the same irradiance (5 standard errors of the difference).
  EXPECT_NEAR(mean[0], mean[1], 5 * std::sqrt((variance[0] + variance[1]) / n));
  EXPECT_LT(variance[0], variance[1] / 100);
  EXPECT_LT(variance[0], mean[0] * mean[0]);
}

}  // namespace
}  // namespace pathfarm
