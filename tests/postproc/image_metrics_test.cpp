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
  EXPECT_EQ(m.compared, 6u);
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
