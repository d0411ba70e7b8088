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

TEST(RadianceCheck, RefusesFramesThatDoNotFit) {
  const FrameImage features = checkFrame([](int, int) { return 1.0f; }, 0.01f);
  EXPECT_THROW(radianceMismatch(FrameImage(2, 2), features), std::invalid_argument);
  EXPECT_THROW(radianceMismatch(checkFrame([](int, int) { return 1.0f; }), checkFrame([](int, int) { return 1.0f; })),
               std::invalid_argument);  // the features have no variance
}

}  // namespace
}  // namespace pathfarm
