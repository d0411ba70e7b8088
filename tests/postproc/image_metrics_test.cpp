#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "postproc/metrics/image_metrics.h"

namespace pathfarm {
namespace {

FrameImage grey(int w, int h, std::vector<float> values) {
  FrameImage f(w, h);
  for (const char* c : {"R", "G", "B"}) f.addChannel(c) = values;
  return f;
}

TEST(ImageMetrics, MatchTheirDefinitionsOnHandComputedValues) {
  const FrameImage image = grey(2, 1, {1.1f, 0.0f});
  const FrameImage ref = grey(2, 1, {1.0f, 0.5f});
  const ImageMetrics m = compareImages(image, ref, {"R", "G", "B"});
  const double d0 = 1.1f - 1.0f;
  EXPECT_NEAR(m.relMse, (d0 * d0 / 1.01 + 0.25 / 0.26) / 2, 1e-7);
  EXPECT_NEAR(m.mse, (d0 * d0 + 0.25) / 2, 1e-7);
  EXPECT_NEAR(m.psnr, 10 * std::log10(1 / m.mse), 1e-9);
  EXPECT_NEAR(m.smape, (2 * d0 / (1.1f + 1.0 + 0.01) + 2 * 0.5 / (0.5 + 0.01)) / 2, 1e-6);
  EXPECT_NEAR(m.brightness, 1.1f / 1.5, 1e-7);
  EXPECT_EQ(m.compared, 6u);
  EXPECT_EQ(compareImages(ref, ref, {"R", "G", "B"}).brightness, 1.0);
}

TEST(ImageMetrics, CropLayersAndNonFiniteReferences) {
  FrameImage image = grey(2, 2, {0, 0, 0, 5});
  FrameImage ref = grey(2, 2, {0, 0, 0, 0});
  EXPECT_EQ(compareImages(image, ref, {"R"}, Crop{0, 0, 2, 1}).mse, 0.0);
  EXPECT_NEAR(compareImages(image, ref, {"R"}).mse, 25.0 / 4, 1e-9);
  ref.channel("G")[3] = std::numeric_limits<float>::quiet_NaN();
  const ImageMetrics m = compareImages(image, ref, {"G"});
  EXPECT_EQ(m.skippedReference, 1u);
  EXPECT_EQ(m.mse, 0.0);
  image.addChannel("diffuse_direct.color.R");
  EXPECT_EQ(layerChannels(image, "diffuse_direct.color"), std::vector<std::string>{"diffuse_direct.color.R"});
  EXPECT_THROW(layerChannels(image, "reflection.color"), std::invalid_argument);
  EXPECT_THROW(compareImages(image, grey(3, 1, {0, 0, 0}), {"R"}), std::invalid_argument);
  EXPECT_THROW(compareImages(image, ref, {"R"}, Crop{1, 1, 3, 2}), std::invalid_argument);
}

// A 40x20 frame (tiles: 3 columns, the last 8 wide; 2 rows, the last 4 high) whose only
// error is 4 wrong pixels in the partial corner tile: relative errors of 1 and 0.25.
TEST(ImageMetrics, WorstTileAndWorstPercentFindAFewWrongPixels) {
  const FrameImage ref = grey(40, 20, std::vector<float>(800, 1.0f));
  FrameImage image = ref;
  const size_t wrong[4] = {19 * 40 + 39, 19 * 40 + 38, 18 * 40 + 39, 16 * 40 + 32};
  const float values[4] = {2.0f, 2.0f, 1.5f, 1.5f};
  for (const char* c : {"R", "G", "B"})
    for (int i = 0; i < 4; ++i) image.channel(c)[wrong[i]] = values[i];
  const ImageMetrics m = compareImages(image, ref, {"R", "G", "B"});
  const double perValue = 1.0 / 1.01, quarter = 0.25 / 1.01;
  EXPECT_NEAR(m.relMse, (2 * perValue + 2 * quarter) / 800, 1e-9);
  // The corner tile has 8x4 pixels: its relMSE is the four pixels' sum over 32.
  EXPECT_NEAR(m.worstTileRelMse, (2 * perValue + 2 * quarter) / 32, 1e-9);
  // The worst 1 % of 800 pixels is 8 pixels: they hold all of the error.
  EXPECT_NEAR(m.worstPercentShare, 1.0, 1e-12);
  // Spread the same error evenly and the share falls to 1 %.
  const FrameImage even = grey(40, 20, std::vector<float>(800, 1.1f));
  EXPECT_NEAR(compareImages(even, ref, {"R"}).worstPercentShare, 0.01, 1e-9);
  EXPECT_NEAR(compareImages(even, ref, {"R"}).worstTileRelMse, 0.01 / 1.01, 1e-6);
  // Measured only on the pixels a mask keeps, the wrong ones out: no error at all.
  std::vector<uint8_t> kept(800, 1);
  for (size_t p : wrong) kept[p] = 0;
  const ImageMetrics masked = compareImages(image, ref, {"R", "G", "B"}, {}, &kept);
  EXPECT_EQ(masked.relMse, 0.0);
  EXPECT_EQ(masked.worstTileRelMse, 0.0);
  EXPECT_EQ(masked.compared, 3u * 796u);
  kept.pop_back();
  EXPECT_THROW(compareImages(image, ref, {"R"}, {}, &kept), std::invalid_argument);
}

TEST(SequenceMetrics, TemporalErrorSeesFlickerThatFrameErrorsMiss) {
  // Both sequences are equally wrong frame by frame, but one flickers and one is steady.
  const std::vector<FrameImage> reference{grey(1, 1, {1}), grey(1, 1, {1}), grey(1, 1, {1})};
  const std::vector<FrameImage> steady{grey(1, 1, {1.2f}), grey(1, 1, {1.2f}), grey(1, 1, {1.2f})};
  const std::vector<FrameImage> flicker{grey(1, 1, {1.2f}), grey(1, 1, {0.8f}), grey(1, 1, {1.2f})};
  const SequenceMetrics s = compareSequences(steady, reference, {"R"});
  const SequenceMetrics f = compareSequences(flicker, reference, {"R"});
  EXPECT_NEAR(s.meanRelMse, f.meanRelMse, 1e-6);
  EXPECT_NEAR(s.temporalRelMse, 0.0, 1e-12);
  EXPECT_NEAR(f.temporalRelMse, 0.16 / 0.01, 1e-3);  // differences of +-0.4 against 0
  EXPECT_THROW(compareSequences(steady, {reference[0]}, {"R"}), std::invalid_argument);
}

}  // namespace
}  // namespace pathfarm
