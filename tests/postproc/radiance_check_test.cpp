#include "postproc/interpolation/radiance_check.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>

namespace pathfarm {
namespace {

constexpr int kCheckSize = 48;

// A one-component frame ("light=ED" and the residual, which stays black) whose light is
// `value(x, y)`; the features carry a per-pixel variance and their beauty.
FrameImage checkFrame(const std::function<float(int, int)>& value, float variance = -1) {
  FrameImage f(kCheckSize, kCheckSize);
  f.attributes()["pathfarm.decomposition"] = "light=ED,residual";
  for (const char* c : {"R", "G", "B"}) {
    const std::string n = c;
    std::vector<float> values(static_cast<size_t>(kCheckSize * kCheckSize));
    for (int y = 0; y < kCheckSize; ++y)
      for (int x = 0; x < kCheckSize; ++x) values[static_cast<size_t>(y * kCheckSize + x)] = value(x, y);
    f.addChannel(n) = values;
    f.addChannel("light.color." + n) = values;
    f.addChannel("residual.color." + n) = std::vector<float>(values.size(), 0.0f);
    if (variance >= 0) {
      f.addChannel("light.variance." + n) = std::vector<float>(values.size(), variance);
      f.addChannel("residual.variance." + n) = std::vector<float>(values.size(), 0.0f);
    }
  }
  return f;
}

bool inDisc(int x, int y) { return (x - 24) * (x - 24) + (y - 24) * (y - 24) < 64; }

size_t flaggedCount(const std::vector<uint8_t>& flags) { return static_cast<size_t>(std::count(flags.begin(), flags.end(), 1)); }

TEST(RadianceCheck, NoiseTheFeaturesVarianceExplainsIsNoMismatch) {
  std::mt19937 random(7);
  std::normal_distribution<float> noise(0.0f, 0.1f);
  std::vector<float> noisy(static_cast<size_t>(kCheckSize * kCheckSize));
  for (float& v : noisy) v = 1.0f + noise(random);
  const FrameImage features = checkFrame([&](int x, int y) { return noisy[static_cast<size_t>(y * kCheckSize + x)]; }, 0.01f);
  EXPECT_EQ(flaggedCount(radianceMismatch(checkFrame([](int, int) { return 1.0f; }), features)), 0u);
}

TEST(RadianceCheck, AGhostIsFlaggedWhereItIsAndNowhereElse) {
  const FrameImage features = checkFrame([](int, int) { return 1.0f; }, 0.01f);
  const FrameImage ghost = checkFrame([](int x, int y) { return inDisc(x, y) ? 1.3f : 1.0f; });
  const std::vector<uint8_t> flags = radianceMismatch(ghost, features);
  EXPECT_EQ(flags[24 * kCheckSize + 24], 1);
  EXPECT_EQ(flags[0], 0);
  EXPECT_EQ(flags[24 * kCheckSize + 40], 0);  // 16 pixels from the centre: outside every window that sees the disc
  EXPECT_GT(flaggedCount(flags), 150u);
}

TEST(RadianceCheck, NoiseOrASmallDifferenceExplainsAway) {
  // The same ghost against features so noisy (variance 1 per pixel) that it could be noise.
  const FrameImage noisy = checkFrame([](int, int) { return 1.0f; }, 1.0f);
  const FrameImage ghost = checkFrame([](int x, int y) { return inDisc(x, y) ? 1.3f : 1.0f; });
  EXPECT_EQ(flaggedCount(radianceMismatch(ghost, noisy)), 0u);
  // A difference of 5 % against exact features: real, but below what is worth a re-render.
  const FrameImage exact = checkFrame([](int, int) { return 1.0f; }, 0.0f);
  const FrameImage slight = checkFrame([](int x, int y) { return inDisc(x, y) ? 1.05f : 1.0f; });
  EXPECT_EQ(flaggedCount(radianceMismatch(slight, exact)), 0u);
  EXPECT_GT(flaggedCount(radianceMismatch(ghost, exact)), 0u);
}

TEST(RadianceCheck, ADifferenceThatOnlyGrazesTheThresholdLeavesNoSpecks) {
  // Features that brighten to the right (1 + 0.02 x) and one pixel at (24, 24) brighter in
  // the interpolated frame by D. The windows holding it have centres x in [21, 27], and a
  // centre passes the relative test when D > 0.1 x 49 (1 + 0.02 x), i.e. x < (D / 4.9 - 1)
  // / 0.02. At D = 7 only x = 21 does: a band 1 pixel wide and 7 tall, which is dropped.
  // At D = 10 every one of them does: the whole 7 x 7 square is flagged, and kept.
  const auto ramp = [](int x, int) { return 1.0f + 0.02f * static_cast<float>(x); };
  const FrameImage features = checkFrame(ramp, 1e-4f);
  const auto brighterAtTheCentre = [&](float d) {
    return checkFrame([&](int x, int y) { return ramp(x, y) + (x == 24 && y == 24 ? d : 0.0f); });
  };
  const FrameImage grazing = brighterAtTheCentre(7.0f);
  RadianceCheckSettings everyFlag;
  everyFlag.solidRadius = 0;
  everyFlag.growRelative = everyFlag.relative;  // no growth: the band alone
  EXPECT_EQ(flaggedCount(radianceMismatch(grazing, features, everyFlag)), 7u);
  EXPECT_EQ(flaggedCount(radianceMismatch(grazing, features)), 0u);
  const std::vector<uint8_t> flags = radianceMismatch(brighterAtTheCentre(10.0f), features);
  EXPECT_EQ(flaggedCount(flags), 49u);
  for (int y = 21; y <= 27; ++y)
    for (int x = 21; x <= 27; ++x) EXPECT_EQ(flags[static_cast<size_t>(y * kCheckSize + x)], 1) << x << ", " << y;
}

// Exact features lit at 1 and an interpolated frame off by 30 % in a 9 x 9 square, by 6 %
// in a ring 6 pixels wide around it, and by 2 % beyond. The square alone passes the
// check's tenth; the region grows through the ring, whose windows are off by more than
// the weaker 4 %, and stops where the windows' difference falls below that.
float softStep(int x, int y) {
  const int d = std::max(std::abs(x - 24), std::abs(y - 24));
  return d <= 4 ? 1.3f : d <= 10 ? 1.06f : 1.02f;
}

TEST(RadianceCheck, AFlaggedRegionGrowsThroughTheWeakerDifferenceAroundIt) {
  const FrameImage features = checkFrame([](int, int) { return 1.0f; }, 1e-6f);
  const std::vector<uint8_t> flags = radianceMismatch(checkFrame(softStep), features);
  for (int y = 0; y < kCheckSize; ++y)
    for (int x = 0; x < kCheckSize; ++x) {
      const int d = std::max(std::abs(x - 24), std::abs(y - 24));
      const uint8_t flag = flags[static_cast<size_t>(y * kCheckSize + x)];
      // A window (7 x 7) centred 2 pixels inside the ring's outer edge still holds enough
      // of it at the ring's corners, and one centred 4 pixels outside holds too little.
      if (d <= 8) {
        EXPECT_EQ(flag, 1) << x << ", " << y;
      }
      if (d >= 12) {
        EXPECT_EQ(flag, 0) << x << ", " << y;
      }
    }
  // Without the square nothing passes the tenth, and nothing grows.
  const std::vector<uint8_t> ringAlone =
      radianceMismatch(checkFrame([](int x, int y) { return std::min(softStep(x, y), 1.06f); }), features);
  EXPECT_EQ(flaggedCount(ringAlone), 0u);
  // With growth turned off, the flags end inside the ring.
  RadianceCheckSettings strongOnly;
  strongOnly.growRelative = strongOnly.relative;
  const std::vector<uint8_t> strong = radianceMismatch(checkFrame(softStep), features, strongOnly);
  EXPECT_EQ(strong[static_cast<size_t>(24 * kCheckSize + 24)], 1);
  EXPECT_EQ(strong[static_cast<size_t>(24 * kCheckSize + 24 + 8)], 0);
}

TEST(RadianceCheck, RefusesFramesThatDoNotFit) {
  const FrameImage features = checkFrame([](int, int) { return 1.0f; }, 0.01f);
  EXPECT_THROW(radianceMismatch(FrameImage(2, 2), features), std::invalid_argument);
  EXPECT_THROW(radianceMismatch(checkFrame([](int, int) { return 1.0f; }), checkFrame([](int, int) { return 1.0f; })),
               std::invalid_argument);  // the features have no variance
}

}  // namespace
}  // namespace pathfarm
