// Fireflies taken out before NL-means: found against their neighbours' level and noise,
// their light kept, spread by a Gaussian whose weights the tests compute on their own,
// and held on their surface.
#include "postproc/filters/firefly_spread.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

namespace pathfarm {
namespace {

constexpr int kFlatSize = 41, kFlatCenter = 20;

// A flat gray image of value 1 with a standard error of 0.1 everywhere.
struct FlatWall {
  Planes color{kFlatSize, kFlatSize, 3}, variance{kFlatSize, kFlatSize, 3};
  FlatWall() {
    for (auto& plane : color.channels) std::fill(plane.begin(), plane.end(), 1.0f);
    for (auto& plane : variance.channels) std::fill(plane.begin(), plane.end(), 0.01f);
  }
  void set(int x, int y, float value, float var) {
    for (int c = 0; c < 3; ++c) {
      color.channels[c][static_cast<size_t>(y * kFlatSize + x)] = value;
      variance.channels[c][static_cast<size_t>(y * kFlatSize + x)] = var;
    }
  }
};

double sumOf(const std::vector<float>& plane) { return std::accumulate(plane.begin(), plane.end(), 0.0); }

// A Gaussian of standard deviation `sigma` summed over a square of half-side `half` around
// its center: the product of two one-dimensional sums.
double gaussianMass(int half, double sigma = 4.0) {
  double line = 0;
  for (int d = -half; d <= half; ++d) line += std::exp(-d * d / (2 * sigma * sigma));
  return line * line;
}

// The spread cut at radius 8 (sigma 4), so that the tests know its weights.
FireflySettings radiusEight() {
  FireflySettings s;
  s.maxRadius = 8;
  return s;
}

TEST(FireflySpread, AFireflysLightIsKeptAndSpreadByTheGaussian) {
  FlatWall image;
  image.set(kFlatCenter, kFlatCenter, 50.0f, 2500.0f);  // one sample of 50 x spp: its error is its value
  const double before = sumOf(image.color.channels[1]);
  const FireflySplit split = splitFireflies(image.color, image.variance, {}, {}, radiusEight());
  ASSERT_EQ(split.fireflies.size(), 1u);
  const size_t center = static_cast<size_t>(kFlatCenter * kFlatSize + kFlatCenter);
  // Clamped to twice its neighbours' median, its relative error unchanged.
  EXPECT_FLOAT_EQ(image.color.channels[1][center], 2.0f);
  EXPECT_NEAR(image.variance.channels[1][center], 2500.0f * (2.0f / 50.0f) * (2.0f / 50.0f), 1e-3f);
  // The excess, 48, spread over the whole window (inside the image) by the Gaussian.
  const double peak = 48.0 / gaussianMass(8);
  EXPECT_NEAR(split.excess.channels[1][center], peak, 1e-5);
  EXPECT_NEAR(split.excess.channels[1][center + 3], peak * std::exp(-9.0 / 32.0), 1e-5);
  EXPECT_EQ(split.excess.channels[1][center + 9], 0.0f);
  EXPECT_NEAR(sumOf(image.color.channels[1]) + sumOf(split.excess.channels[1]), before, 1e-3);
  // No pixel left brighter than a few tenths above the wall.
  for (size_t p = 0; p < image.color.pixelCount(); ++p)
    EXPECT_LT(image.color.channels[1][p] + split.excess.channels[1][p], p == center ? 2.6f : 1.5f);
}

TEST(FireflySpread, ABrighterFireflySpreadsFartherToTheSameFaintGlow) {
  // The radius is the smallest whose Gaussian (sigma half of it, cut to the square) peaks
  // at `glow` times the wall's level or less.
  const double glow = FireflySettings{}.glow;
  for (const float light : {20.0f, 50.0f}) {
    FlatWall image;
    image.set(kFlatCenter, kFlatCenter, light, light * light);
    const FireflySplit split = splitFireflies(image.color, image.variance, {}, {});
    ASSERT_EQ(split.fireflies.size(), 1u);
    const double excess = light - 2.0;
    int radius = 1;
    while (excess / gaussianMass(radius, radius / 2.0) > glow) ++radius;
    const double peak = excess / gaussianMass(radius, radius / 2.0);
    const size_t center = static_cast<size_t>(kFlatCenter * kFlatSize + kFlatCenter);
    EXPECT_NEAR(split.excess.channels[0][center], peak, 1e-5) << light;
    EXPECT_GT(peak, 0.8 * glow);  // not spread wider than it needs
    EXPECT_LE(radius, kFlatCenter);
    EXPECT_NEAR(sumOf(split.excess.channels[0]), excess, 1e-3);
  }
}

TEST(FireflySpread, ACrowdOfThemIsACausticAndKeepsItsLight) {
  // A 7x7 patch where every pixel found the same bright, rare path: a caustic that few
  // samples found. Each pixel's neighbours lift its level above half its light, but at
  // the corners ((7 x 20 + 16) / 23 = 6.8) and beside them ((10 x 20 + 13) / 23 = 9.3).
  FlatWall caustic;
  for (int y = kFlatCenter - 3; y <= kFlatCenter + 3; ++y)
    for (int x = kFlatCenter - 3; x <= kFlatCenter + 3; ++x) caustic.set(x, y, 20.0f, 400.0f);
  const double before = sumOf(caustic.color.channels[0]);
  const FireflySplit split = splitFireflies(caustic.color, caustic.variance, {}, {});
  EXPECT_EQ(split.fireflies.size(), 12u);
  double inside = 0;
  for (int y = kFlatCenter - 3; y <= kFlatCenter + 3; ++y)
    for (int x = kFlatCenter - 3; x <= kFlatCenter + 3; ++x) {
      const size_t p = static_cast<size_t>(y * kFlatSize + x);
      inside += caustic.color.channels[0][p] + split.excess.channels[0][p];
    }
  EXPECT_GT(inside, 0.9 * 49 * 20.0);  // most of its light stays on the patch
  EXPECT_NEAR(sumOf(caustic.color.channels[0]) + sumOf(split.excess.channels[0]), before, 1e-2);
  // Two alone in a window are both fireflies.
  FlatWall pair;
  pair.set(kFlatCenter, kFlatCenter, 20.0f, 400.0f);
  pair.set(kFlatCenter + 1, kFlatCenter + 1, 20.0f, 400.0f);
  EXPECT_EQ(splitFireflies(pair.color, pair.variance, {}, {}).fireflies.size(), 2u);
}

TEST(FireflySpread, ABrightDetailEverySampleSeesIsKept) {
  FlatWall image;
  image.set(kFlatCenter, kFlatCenter, 50.0f, 0.25f);  // bright, but a standard error of 1 %
  const Planes before = image.color;
  const FireflySplit split = splitFireflies(image.color, image.variance, {}, {});
  EXPECT_EQ(split.fireflies.size(), 0u);
  EXPECT_EQ(image.color.channels, before.channels);
  EXPECT_EQ(sumOf(split.excess.channels[0]), 0.0);
}

TEST(FireflySpread, NoiseOfTheNeighboursOwnSizeIsNoFirefly) {
  FlatWall image;
  for (auto& plane : image.variance.channels) std::fill(plane.begin(), plane.end(), 1.0f);  // error 1 on a value of 1
  image.set(kFlatCenter, kFlatCenter, 3.5f, 4.0f);  // 2.5 of its neighbours' errors above: noise, not a firefly
  EXPECT_EQ(splitFireflies(image.color, image.variance, {}, {}).fireflies.size(), 0u);
  image.set(kFlatCenter, kFlatCenter, 5.5f, 4.0f);  // 4.5 errors above
  EXPECT_EQ(splitFireflies(image.color, image.variance, {}, {}).fireflies.size(), 1u);
}

TEST(FireflySpread, TheLightStaysOnItsSurface) {
  FlatWall image;
  Planes objectId(kFlatSize, kFlatSize, 1), normal(kFlatSize, kFlatSize, 3);
  for (int y = 0; y < kFlatSize; ++y)
    for (int x = 0; x < kFlatSize; ++x) {
      const size_t p = static_cast<size_t>(y * kFlatSize + x);
      objectId.channels[0][p] = x < kFlatCenter + 2 ? 1.0f : 2.0f;  // another object from x = 22
      normal.channels[2][p] = 1.0f;
      if (y > kFlatCenter + 2) normal.channels[0][p] = 1.0f;  // a fold (45 degrees) below y = 22
    }
  image.set(kFlatCenter, kFlatCenter, 50.0f, 2500.0f);
  const FireflySplit split = splitFireflies(image.color, image.variance, {}, {&normal, &objectId}, radiusEight());
  ASSERT_EQ(split.fireflies.size(), 1u);
  double kept = 0;
  for (int y = 0; y < kFlatSize; ++y)
    for (int x = 0; x < kFlatSize; ++x) {
      const float excess = split.excess.channels[0][static_cast<size_t>(y * kFlatSize + x)];
      if (x >= kFlatCenter + 2 || y > kFlatCenter + 2) {
        EXPECT_EQ(excess, 0.0f) << x << ", " << y;
      }
      kept += excess;
    }
  EXPECT_NEAR(kept, 48.0, 1e-3);  // all of it, on the firefly's side
}

TEST(FireflySpread, AShadowBesideTheFireflyTakesLittle) {
  // The same surface, lit at 1 left of x = 24 and at 0.1 from there: a receiver takes in
  // proportion to its 3x3 window's light, so at equal distance a pixel deep in the shadow
  // takes a tenth of what a lit one does.
  FlatWall image;
  for (int y = 0; y < kFlatSize; ++y)
    for (int x = 24; x < kFlatSize; ++x) image.set(x, y, 0.1f, 1e-4f);
  image.set(kFlatCenter, kFlatCenter, 50.0f, 2500.0f);
  const FireflySplit split = splitFireflies(image.color, image.variance, {}, {}, radiusEight());
  ASSERT_EQ(split.fireflies.size(), 1u);
  const auto at = [&](int x, int y) { return split.excess.channels[0][static_cast<size_t>(y * kFlatSize + x)]; };
  EXPECT_NEAR(at(kFlatCenter + 6, kFlatCenter), 0.1f * at(kFlatCenter - 6, kFlatCenter), 1e-6f);
  EXPECT_NEAR(at(kFlatCenter + 5, kFlatCenter + 3), 0.1f * at(kFlatCenter - 5, kFlatCenter + 3), 1e-6f);
  EXPECT_NEAR(sumOf(split.excess.channels[0]), 48.0, 1e-3);  // all of it still
}

TEST(FireflySpread, PixelsWithoutASampleTakeTheirShareAway) {
  // A 3x3 clump of rendered pixels (as the composite's re-rendered ones) holding a firefly:
  // the clump keeps the share of the Gaussian that falls on it, not all of the light.
  FlatWall image;
  std::vector<float> valid(image.color.pixelCount(), 0.0f);
  for (int y = kFlatCenter - 1; y <= kFlatCenter + 1; ++y)
    for (int x = kFlatCenter - 1; x <= kFlatCenter + 1; ++x) valid[static_cast<size_t>(y * kFlatSize + x)] = 1.0f;
  image.set(kFlatCenter, kFlatCenter, 50.0f, 2500.0f);
  const FireflySplit split = splitFireflies(image.color, image.variance, valid, {}, radiusEight());
  ASSERT_EQ(split.fireflies.size(), 1u);
  EXPECT_NEAR(sumOf(split.excess.channels[2]), 48.0 * gaussianMass(1) / gaussianMass(8), 1e-4);
  for (size_t p = 0; p < valid.size(); ++p)
    if (valid[p] == 0.0f) {
      EXPECT_EQ(split.excess.channels[2][p], 0.0f);
    }
}

TEST(FireflySpread, MismatchedPlanesAreRefused) {
  FlatWall image;
  Planes small(kFlatSize - 1, kFlatSize, 3);
  EXPECT_THROW(splitFireflies(image.color, small, {}, {}), std::invalid_argument);
  EXPECT_THROW(splitFireflies(image.color, image.variance, std::vector<float>(3, 1.0f), {}), std::invalid_argument);
  Planes objectId(kFlatSize, kFlatSize, 2);
  EXPECT_THROW(splitFireflies(image.color, image.variance, {}, {nullptr, &objectId}), std::invalid_argument);
}

}  // namespace
}  // namespace pathfarm
