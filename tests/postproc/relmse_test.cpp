#include <gtest/gtest.h>

#include "postproc/metrics/relmse.h"
#include "test_support.h"

namespace pathfarm {
namespace {

TEST(RelMse, MatchesTheDefinitionOnHandComputedValues) {
  // (1.1-1)^2/(1+0.01) = 0.0099010, (0-0)^2 = 0, (3-2)^2/(4+0.01) = 0.2493766
  const double expected = (0.01 / 1.01 + 0.0 + 1.0 / 4.01) / 3.0;
  EXPECT_NEAR(relMse({1.1f, 0.0f, 3.0f}, {1.0f, 0.0f, 2.0f}), expected, 1e-7);
  EXPECT_EQ(relMse({1, 2, 3}, {1, 2, 3}), 0.0);
  EXPECT_THROW(relMse({1, 2}, {1, 2, 3}), std::invalid_argument);
}

TEST(RelMse, AveragesTheBeautyChannels) {
  FrameImage a(1, 1), b(1, 1);
  for (const char* c : {"R", "G", "B"}) {
    a.addChannel(c)[0] = 1;
    b.addChannel(c)[0] = 0;
  }
  a.channel("G")[0] = 0;
  EXPECT_NEAR(relMse(a, b), (2.0 / 0.01) / 3.0, 1e-9);
}

TEST(RelMse, ExpectedFromTheVarianceMatchesTheDefinitionOnHandComputedValues) {
  FrameImage image(2, 1);
  for (const char* c : {"R", "G", "B"}) {
    image.addChannel(c) = {1, 0};
    image.addChannel(std::string("variance.") + c) = {0.5f, 0.02f};
  }
  EXPECT_NEAR(expectedRelMse(image), (0.5 / 1.01 + 0.02 / 0.01) / 2, 1e-7);
  FrameImage bare(2, 1);
  for (const char* c : {"R", "G", "B"}) bare.addChannel(c);
  EXPECT_THROW(expectedRelMse(bare), std::invalid_argument);
}

// Each pixel the mean of 16 draws around the truth 1 (uniform, half-width 0.5), with the
// variance of that mean estimated from the draws as a renderer does.
FrameImage noisyRenderOfOne(int w, int h, int seed) {
  const int draws = 16;
  FrameImage image(w, h);
  for (int c = 0; c < 3; ++c) {
    const std::string name = std::string(1, "RGB"[c]);
    auto& value = image.addChannel(name);
    auto& variance = image.addChannel("variance." + name);
    for (size_t p = 0; p < value.size(); ++p) {
      double sum = 0, squares = 0;
      for (int i = 0; i < draws; ++i) {
        const double x = 0.5 + test_support::hashed(seed, c, static_cast<int>(p), i);
        sum += x;
        squares += x * x;
      }
      const double mean = sum / draws;
      value[p] = static_cast<float>(mean);
      variance[p] = static_cast<float>((squares / draws - mean * mean) * draws / (draws - 1) / draws);
    }
  }
  return image;
}

FrameImage constantImage(int w, int h, float value) {
  FrameImage image(w, h);
  for (const char* c : {"R", "G", "B"}) image.addChannel(c).assign(static_cast<size_t>(w) * h, value);
  return image;
}

TEST(RelMse, ExpectedFromTheVarianceIsTheErrorAgainstTheTruth) {
  // Over 30,000 values the expected relMSE and the one measured against the truth agree
  // within 5 % (the measured one's standard error is under 1 %).
  const FrameImage image = noisyRenderOfOne(100, 100, 11), truth = constantImage(100, 100, 1.0f);
  const double measured = relMse(image, truth), expected = expectedRelMse(image);
  EXPECT_NEAR(expected / measured, 1.0, 0.05) << expected << " " << measured;
}

TEST(RelMse, LessTheReferenceNoiseEstimatesTheErrorAgainstTheTruth) {
  // An image off the truth 1 by 0.1 everywhere has relMSE 0.01 / 1.01 against it. Against
  // a noisy reference whose own relMSE (about 0.005) is half that, plain relMSE reads
  // about 1.5x too high; less the reference's noise it reads right within 5 %.
  const FrameImage biased = constantImage(100, 100, 1.1f);
  const FrameImage reference = noisyRenderOfOne(100, 100, 23);
  const double truth = 0.01 / 1.01;
  EXPECT_GT(relMse(biased, reference) / truth, 1.3);
  EXPECT_NEAR(relMseLessReferenceNoise(biased, reference).mean() / truth, 1.0, 0.05);
  // Off the other way by as much, the same.
  EXPECT_NEAR(relMseLessReferenceNoise(constantImage(100, 100, 0.9f), reference).mean() / truth, 1.0, 0.05);
  // The truth itself measures as no error, within the reference's noise of zero.
  EXPECT_NEAR(relMseLessReferenceNoise(constantImage(100, 100, 1.0f), reference).mean(), 0.0, 0.05 * truth);
  // And the reference's own error, from its variance, is what it measures against the truth.
  EXPECT_NEAR(ownRelMseFromVariance(reference).mean() / relMse(reference, constantImage(100, 100, 1.0f)), 1.0, 0.05);
}

TEST(RelMse, TheEstimatesStandardErrorIsTheSpreadOfEstimatesFromIndependentReferences) {
  // 48 references of the same truth, each 64x64: the estimates of one biased image spread
  // as their standard errors say, within the 30 % (3 standard deviations) a sample of 48
  // allows.
  const int references = 48;
  const FrameImage biased = constantImage(64, 64, 1.1f);
  std::vector<double> means;
  double standardErrors = 0;
  for (int seed = 0; seed < references; ++seed) {
    const MeanEstimate estimate = relMseLessReferenceNoise(biased, noisyRenderOfOne(64, 64, 100 + seed));
    means.push_back(estimate.mean());
    standardErrors += estimate.standardError() / references;
  }
  double average = 0, spread = 0;
  for (const double m : means) average += m / references;
  for (const double m : means) spread += (m - average) * (m - average) / (references - 1);
  EXPECT_NEAR(std::sqrt(spread) / standardErrors, 1.0, 0.3);
  // Estimates of several frames add up to the estimate of all their terms.
  const FrameImage small = constantImage(40, 40, 1.1f);
  MeanEstimate both = relMseLessReferenceNoise(small, noisyRenderOfOne(40, 40, 1));
  both += relMseLessReferenceNoise(small, noisyRenderOfOne(40, 40, 2));
  EXPECT_EQ(both.count, 2.0 * 3 * 40 * 40);
  EXPECT_EQ(both.blocks, 2.0 * 5 * 5);
}

}  // namespace
}  // namespace pathfarm
