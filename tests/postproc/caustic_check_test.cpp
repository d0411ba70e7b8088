#include "postproc/interpolation/caustic_check.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <functional>

namespace pathfarm {
namespace {

constexpr int kSize = 40;

// A frame lit evenly at 1, plus the moving caustic `caustic(x, y)` (part of the beauty).
FrameImage frame(const std::function<float(int, int)>& caustic) {
  FrameImage f(kSize, kSize);
  std::vector<float> beauty(static_cast<size_t>(kSize * kSize)), focused(beauty.size());
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const auto p = static_cast<size_t>(y * kSize + x);
      focused[p] = caustic(x, y);
      beauty[p] = 1.0f + focused[p];
    }
  for (const char* c : {"R", "G", "B"}) f.addChannel(c) = beauty;
  f.addChannel("moving_caustic.Y") = focused;
  return f;
}

size_t count(const std::vector<uint8_t>& flags) { return static_cast<size_t>(std::count(flags.begin(), flags.end(), 1)); }

TEST(CausticCheck, ASpotIsFlaggedWithItsMarginAndNothingElse) {
  // A 4x4 spot three times as bright as the light around it.
  const auto inSpot = [](int x, int y) { return x >= 10 && x < 14 && y >= 20 && y < 24; };
  const std::vector<uint8_t> flags = movingCausticPixels(frame([&](int x, int y) { return inSpot(x, y) ? 3.0f : 0.0f; }));
  const CausticCheckSettings defaults;
  const int reach = defaults.radius + defaults.margin;  // a window touching the spot, then the margin
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const bool near = x >= 10 - reach && x < 14 + reach && y >= 20 - reach && y < 24 + reach;
      const uint8_t flag = flags[static_cast<size_t>(y * kSize + x)];
      if (inSpot(x, y)) {
        EXPECT_EQ(flag, 1) << x << "," << y;
      }
      if (!near) {
        EXPECT_EQ(flag, 0) << x << "," << y;
      }
    }
}

TEST(CausticCheck, AFireflyOrAFaintWideCausticIsNotASpot) {
  // One bright sample alone: fewer pixels than minPixels saw any caustic in any window.
  EXPECT_EQ(count(movingCausticPixels(frame([](int x, int y) { return x == 20 && y == 20 ? 50.0f : 0.0f; }))), 0u);
  // Everywhere a caustic of 5 % of the light: below the share.
  EXPECT_EQ(count(movingCausticPixels(frame([](int, int) { return 0.05f; }))), 0u);
  // The same at 20 %: every pixel.
  EXPECT_EQ(count(movingCausticPixels(frame([](int, int) { return 0.25f; }))), static_cast<size_t>(kSize * kSize));
}

TEST(CausticCheck, ASparseLowSampleCausticIsFoundWhole) {
  // A render with few samples hits a caustic disc of radius 6 in a third of its pixels:
  // the flags cover the whole disc.
  std::srand(7);
  std::vector<float> hits(static_cast<size_t>(kSize * kSize), 0.0f);
  for (float& h : hits) h = std::rand() % 3 == 0 ? 6.0f : 0.0f;
  const auto inDisc = [](int x, int y) { return (x - 20) * (x - 20) + (y - 20) * (y - 20) <= 36; };
  const std::vector<uint8_t> flags = movingCausticPixels(
      frame([&](int x, int y) { return inDisc(x, y) ? hits[static_cast<size_t>(y * kSize + x)] : 0.0f; }));
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x)
      if (inDisc(x, y)) {
        EXPECT_EQ(flags[static_cast<size_t>(y * kSize + x)], 1) << x << "," << y;
      }
}

// A 4-spp render's pixels: a pixel whose caustic came from `hits` of its 4 samples, each
// carrying `sample`, has the mean hits * sample / 4 and, from its samples' spread, the
// variance of that mean (sample variance over 4; the evenly lit rest has none).
FrameImage sampled(const std::function<int(int, int)>& hits, float sample) {
  FrameImage f = frame([&](int x, int y) { return static_cast<float>(hits(x, y)) * sample / 4.0f; });
  std::vector<float> variance(f.pixelCount(), 0.0f);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const float k = static_cast<float>(hits(x, y)), mean = k * sample / 4.0f;
      const float squares = k * (sample - mean) * (sample - mean) + (4.0f - k) * mean * mean;
      variance[static_cast<size_t>(y * kSize + x)] = squares / 3.0f / 4.0f;
    }
  for (const char* c : {"variance.R", "variance.G", "variance.B"}) f.addChannel(c) = variance;
  return f;
}

TEST(CausticCheck, AWideGlowInRareHeavySamplesIsNotASpotAndAFocusedOneIs) {
  // A moving glass ball's reflection of a lamp, over the whole floor: 5 % of its light on
  // average, arriving as one heavy sample in one pixel of ten. By chance some windows hold
  // enough of them to pass the share; their noise explains it.
  std::srand(11);
  std::vector<int> glow(static_cast<size_t>(kSize * kSize));
  for (int& h : glow) h = std::rand() % 10 == 0 ? 1 : 0;
  const auto glowHits = [&](int x, int y) { return glow[static_cast<size_t>(y * kSize + x)]; };
  CausticCheckSettings noiseless;
  noiseless.z = 0.0f;
  ASSERT_GT(count(movingCausticPixels(sampled(glowHits, 2.0f), noiseless)), 0u) << "the case must pass the share";
  EXPECT_EQ(count(movingCausticPixels(sampled(glowHits, 2.0f))), 0u);
  // A focused spot under the ball, a disc of radius 6 whose pixels see it in half their
  // samples at twice the light around: found whole.
  const auto inDisc = [](int x, int y) { return (x - 20) * (x - 20) + (y - 20) * (y - 20) <= 36; };
  const std::vector<uint8_t> flags = movingCausticPixels(sampled([&](int x, int y) { return inDisc(x, y) ? 2 : 0; }, 4.0f));
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x)
      if (inDisc(x, y)) EXPECT_EQ(flags[static_cast<size_t>(y * kSize + x)], 1) << x << "," << y;
}

TEST(CausticCheck, AFrameWithoutTheBufferHasNoneAndOneWithoutABeautyIsRefused) {
  FrameImage plain(8, 8);
  for (const char* c : {"R", "G", "B"}) plain.addChannel(c);
  EXPECT_EQ(count(movingCausticPixels(plain)), 0u);
  FrameImage noBeauty(8, 8);
  noBeauty.addChannel("moving_caustic.Y");
  EXPECT_THROW(movingCausticPixels(noBeauty), std::invalid_argument);
}

TEST(CausticCheck, ABandOfRowsWithTheCheckReachAroundItHasTheWholeFramesFlags) {
  // Small spots of every strength, sparse enough that a spot just outside the band's reach
  // would change flags inside it, weak ones beside strong ones.
  const FrameImage whole = frame([](int x, int y) {
    const unsigned h = (static_cast<unsigned>(x) * 73856093u) ^ (static_cast<unsigned>(y) * 19349663u);
    return h % 23 == 0 ? static_cast<float>(h % 1000) / 97.0f : 0.0f;
  });
  const std::vector<uint8_t> flags = movingCausticPixels(whole);
  ASSERT_GT(count(flags), 0u);
  ASSERT_LT(count(flags), flags.size() / 2);
  const int first = 13, end = 27;
  const auto bandFlags = [&](int reach) {
    return movingCausticPixels(whole.crop(0, first - reach, kSize, end - first + 2 * reach));
  };
  const auto differing = [&](int reach) {
    const std::vector<uint8_t> band = bandFlags(reach);
    size_t differ = 0;
    for (int y = first; y < end; ++y)
      for (int x = 0; x < kSize; ++x)
        differ += band[static_cast<size_t>((y - first + reach) * kSize + x)] != flags[static_cast<size_t>(y * kSize + x)];
    return differ;
  };
  EXPECT_EQ(differing(causticCheckReach({})), 0u);
  EXPECT_GT(differing(causticCheckReach({}) - 2), 0u) << "a band with fewer rows around it is not told apart";
}

}  // namespace
}  // namespace pathfarm
