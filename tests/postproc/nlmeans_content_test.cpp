// jointNlMeansOnContent against jointNlMeans itself: the same bits, exact zeros away from
// what the frames hold, the same broken-pixel counts and errors; and a window of rows cut
// out of the frames filters to the whole frames' bits.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

#include "postproc/filters/nlmeans.h"

namespace pathfarm {
namespace {

constexpr int kContentWidth = 96, kContentHeight = 72;

// Two frames (the second a neighbour with a few invalid pixels), noisy color and variance
// only inside [x0, x0 + 14) x [y0, y0 + 10), a normal-like feature everywhere.
NlMeansInput sparseInput(int x0, int y0, std::mt19937& rng) {
  std::uniform_real_distribution<float> value(0.0f, 2.0f), variance(0.01f, 0.2f), feature(-1.0f, 1.0f);
  NlMeansInput input;
  input.featureKinds = {FeatureKind::Continuous};
  for (int f = 0; f < 2; ++f) {
    NlMeansFrame& frame = input.frames.emplace_back();
    frame.color = Planes(kContentWidth, kContentHeight, 3);
    frame.variance = Planes(kContentWidth, kContentHeight, 3);
    frame.features.push_back(Planes(kContentWidth, kContentHeight, 3));
    for (auto& channel : frame.features[0].channels)
      for (float& v : channel) v = feature(rng);
    for (int y = y0 + f; y < y0 + 10 + f; ++y)
      for (int x = x0; x < x0 + 14; ++x)
        for (int c = 0; c < 3; ++c) {
          const size_t p = static_cast<size_t>(y) * kContentWidth + x;
          frame.color.channels[static_cast<size_t>(c)][p] = value(rng);
          frame.variance.channels[static_cast<size_t>(c)][p] = variance(rng);
        }
    if (f == 1) {
      frame.valid.assign(static_cast<size_t>(kContentWidth) * kContentHeight, 1.0f);
      for (size_t p = 0; p < frame.valid.size(); p += 7) frame.valid[p] = 0.0f;
    }
  }
  return input;
}

void expectSameImage(const Planes& cropped, const Planes& whole) {
  ASSERT_EQ(cropped.width, whole.width);
  ASSERT_EQ(cropped.height, whole.height);
  ASSERT_EQ(cropped.channels.size(), whole.channels.size());
  for (size_t c = 0; c < whole.channels.size(); ++c)
    for (size_t p = 0; p < whole.pixelCount(); ++p) {
      ASSERT_EQ(std::bit_cast<uint32_t>(cropped.channels[c][p]), std::bit_cast<uint32_t>(whole.channels[c][p]))
          << "channel " << c << " pixel " << p;
    }
}

// Rows [first, end) of every plane of every frame.
Planes planeRows(const Planes& planes, int first, int end) {
  Planes out(planes.width, end - first, static_cast<int>(planes.channels.size()));
  for (size_t c = 0; c < planes.channels.size(); ++c)
    std::copy(planes.channels[c].begin() + static_cast<std::ptrdiff_t>(first) * planes.width,
              planes.channels[c].begin() + static_cast<std::ptrdiff_t>(end) * planes.width, out.channels[c].begin());
  return out;
}

TEST(NlMeansOnContent, FiltersLikeTheWholeFrameWhereverTheContentSits) {
  std::mt19937 rng(11);
  const NlMeansSettings settings{.radius = 5, .patch = 3};
  // Inside the frame, and against two of its edges.
  for (const auto& [x0, y0] : {std::pair{40, 30}, std::pair{0, 0}, std::pair{82, 61}}) {
    const NlMeansInput input = sparseInput(x0, y0, rng);
    const Planes whole = jointNlMeans(input, settings);
    const Planes cropped = jointNlMeansOnContent(input, settings);
    expectSameImage(cropped, whole);
    double sum = 0;
    for (float v : whole.channels[0]) sum += v;
    EXPECT_GT(sum, 0.0) << "the content was filtered, not dropped";
  }
}

TEST(NlMeansOnContent, AWantedAreaIsFilteredLikeTheWholeFrame) {
  std::mt19937 rng(7);
  NlMeansInput input = sparseInput(20, 20, rng);
  // Every pixel holds something (as the composite's invalid, NaN pixels do), so only the
  // wanted area bounds the work.
  for (NlMeansFrame& frame : input.frames) {
    for (auto& channel : frame.color.channels)
      for (float& v : channel) v += 0.5f;
    for (auto& channel : frame.variance.channels)
      for (float& v : channel) v += 0.05f;
  }
  const NlMeansSettings settings{.radius = 3, .patch = 2};
  const Planes whole = jointNlMeans(input, settings);
  const NlMeansArea wanted{24, 22, 30, 27};
  const Planes part = jointNlMeansOnContent(input, settings, nullptr, &wanted);
  for (size_t c = 0; c < whole.channels.size(); ++c)
    for (int y = wanted.y0; y < wanted.y1; ++y)
      for (int x = wanted.x0; x < wanted.x1; ++x) {
        const size_t p = static_cast<size_t>(y) * kContentWidth + x;
        ASSERT_EQ(std::bit_cast<uint32_t>(part.channels[c][p]), std::bit_cast<uint32_t>(whole.channels[c][p]));
      }
  // Far from it, nothing was filtered.
  EXPECT_EQ(part.channels[0][static_cast<size_t>(60) * kContentWidth + 80], 0.0f);
  EXPECT_NE(whole.channels[0][static_cast<size_t>(60) * kContentWidth + 80], 0.0f);
}

TEST(NlMeansOnContent, OnlyValidCentersAreFilteredLikeTheWholeFrame) {
  std::mt19937 rng(11);
  NlMeansInput input = sparseInput(20, 20, rng);
  input.frames.resize(1);
  // A sparse frame, as the composite's re-rendered pixels are: a diagonal band, a lone
  // pixel far from it, and rows with none.
  NlMeansFrame& frame = input.frames[0];
  frame.valid.assign(static_cast<size_t>(kContentWidth) * kContentHeight, 0.0f);
  for (int y = 18; y < 34; ++y)
    for (int x = y; x < y + 4; ++x) frame.valid[static_cast<size_t>(y) * kContentWidth + x] = 1.0f;
  frame.valid[static_cast<size_t>(50) * kContentWidth + 70] = 1.0f;
  for (auto& channel : frame.color.channels)
    for (float& v : channel) v += 0.5f;
  const NlMeansSettings settings{.radius = 3, .patch = 2};
  NlMeansSettings sparse = settings;
  sparse.validCentersOnly = true;
  const Planes whole = jointNlMeans(input, settings);
  const Planes part = jointNlMeans(input, sparse);
  size_t valid = 0;
  for (size_t c = 0; c < whole.channels.size(); ++c)
    for (size_t p = 0; p < whole.pixelCount(); ++p) {
      if (frame.valid[p] > 0.0f) {
        ++valid;
        ASSERT_NEAR(part.channels[c][p], whole.channels[c][p], 1e-5f * std::abs(whole.channels[c][p]) + 1e-7f) << p;
      } else {
        ASSERT_EQ(part.channels[c][p], 0.0f) << p;  // jointNlMeans fills these from their neighbours
      }
    }
  EXPECT_EQ(valid, 3u * 65u);
  EXPECT_NE(whole.channels[0][static_cast<size_t>(18) * kContentWidth + 23], 0.0f);
}

TEST(NlMeansOnContent, BrokenPixelsAreContentAndCountedTheSame) {
  std::mt19937 rng(5);
  NlMeansInput input = sparseInput(30, 20, rng);
  // A NaN far from the rest: it is filled from its neighbours (zeros) in both.
  input.frames[0].color.channels[1][static_cast<size_t>(60) * kContentWidth + 85] = std::numeric_limits<float>::quiet_NaN();
  const NlMeansSettings settings{.radius = 3, .patch = 2};
  NlMeansStats wholeStats, croppedStats;
  const Planes whole = jointNlMeans(input, settings, &wholeStats);
  const Planes cropped = jointNlMeansOnContent(input, settings, &croppedStats);
  expectSameImage(cropped, whole);
  EXPECT_EQ(croppedStats.invalidCenters, wholeStats.invalidCenters);
  EXPECT_EQ(croppedStats.unfilledCenters, wholeStats.unfilledCenters);
  EXPECT_EQ(croppedStats.invalidCenter, wholeStats.invalidCenter);
}

TEST(NlMeansOnContent, NothingAnywhereIsZeroAndMismatchedInputIsRefusedAlike) {
  NlMeansInput empty;
  empty.frames.emplace_back();
  empty.frames[0].color = Planes(kContentWidth, kContentHeight, 3);
  empty.frames[0].variance = Planes(kContentWidth, kContentHeight, 3);
  const Planes zero = jointNlMeansOnContent(empty, NlMeansSettings{});
  for (const auto& channel : zero.channels)
    for (float v : channel) ASSERT_EQ(v, 0.0f);
  NlMeansInput mismatched = empty;
  mismatched.frames[0].variance = Planes(kContentWidth - 1, kContentHeight, 3);
  EXPECT_THROW(jointNlMeansOnContent(mismatched, NlMeansSettings{}), std::invalid_argument);
}

// A window of rows with radius + patch rows around it, filtered alone (its bands start
// elsewhere: 37 is no multiple of the filter's bands), is the whole frames' filter there,
// bit for bit, and one row fewer around it is not.
TEST(NlMeansOnContent, AWindowOfRowsWithItsReachIsTheWholeFramesBits) {
  std::mt19937 rng(5);
  const NlMeansSettings settings{.radius = 5, .patch = 3};
  const int first = 45, end = 61, reach = settings.radius + settings.patch;
  // Rows [first - margin, end + margin) of the frames, filtered, at rows [first, end).
  const auto window = [&](const NlMeansInput& input, int margin) {
    NlMeansInput part;
    part.featureKinds = input.featureKinds;
    for (const NlMeansFrame& frame : input.frames) {
      NlMeansFrame& rows = part.frames.emplace_back();
      rows.color = planeRows(frame.color, first - margin, end + margin);
      rows.variance = planeRows(frame.variance, first - margin, end + margin);
      rows.features.push_back(planeRows(frame.features[0], first - margin, end + margin));
      if (!frame.valid.empty())
        rows.valid.assign(frame.valid.begin() + static_cast<std::ptrdiff_t>(first - margin) * kContentWidth,
                          frame.valid.begin() + static_cast<std::ptrdiff_t>(end + margin) * kContentWidth);
    }
    return planeRows(jointNlMeans(part, settings), margin, margin + end - first);
  };
  // Noisy light, and a dim, nearly even wall with a few bright specks and no variance (the
  // specks' distances at the clamp, the wall's tiny: the sums' widest range of magnitudes).
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  size_t shortDiffers = 0;
  for (const bool specks : {false, true}) {
    NlMeansInput input = sparseInput(0, 0, rng);
    for (NlMeansFrame& frame : input.frames)
      for (size_t c = 0; c < 3; ++c)
        for (size_t p = 0; p < frame.color.pixelCount(); ++p) {
          const bool speck = uniform(rng) < 0.03f;
          frame.color.channels[c][p] =
              specks ? (speck ? 1.0f : 1e-3f * (1.0f + 1e-6f * uniform(rng))) : 2.0f * uniform(rng);
          frame.variance.channels[c][p] = specks ? 0.0f : 0.05f;
        }
    const Planes wanted = planeRows(jointNlMeans(input, settings), first, end);
    SCOPED_TRACE(specks ? "a wall with specks" : "noisy light");
    expectSameImage(window(input, reach), wanted);
    const Planes short_ = window(input, reach - 1);
    for (size_t c = 0; c < wanted.channels.size(); ++c)
      for (size_t p = 0; p < wanted.pixelCount(); ++p) shortDiffers += short_.channels[c][p] != wanted.channels[c][p];
  }
  EXPECT_GT(shortDiffers, 0u) << "a row less of reach changes the window's edge rows";
}

}  // namespace
}  // namespace pathfarm
