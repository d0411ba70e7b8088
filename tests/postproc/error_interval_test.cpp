// Errors against the truth with their intervals, measured against a noisy reference, on
// pictures whose truth is known: how often the interval holds the true relMSE, how it
// narrows as the reference improves, and what a ratio of two errors claims.
#include "postproc/metrics/error_interval.h"

#include <gtest/gtest.h>

#include "postproc/metrics/relmse.h"
#include "test_support.h"

namespace pathfarm {
namespace {

constexpr int kPictureSize = 64;
constexpr double kPictureSigma = 0.05;
// A reference at `spp` samples: a sample's standard deviation 0.4, its mean's 0.4/sqrt(spp).
double referenceSigma(int spp) { return 0.4 / std::sqrt(static_cast<double>(spp)); }

TEST(ErrorInterval, HoldsTheTrueRelMseAtLeastNineTimesInTen) {
  const FrameImage truth = test_support::smoothTruth(kPictureSize, kPictureSize);
  int held = 0;
  for (uint64_t trial = 0; trial < 100; ++trial) {
    const FrameImage image = test_support::noisyCopy(truth, kPictureSigma, 2 * trial + 1, false);
    const FrameImage reference = test_support::noisyCopy(truth, referenceSigma(256), 2 * trial + 2, true);
    const Interval interval = meanInterval(errorTerms(&image, reference));
    if (interval.contains(relMse(image, truth))) ++held;
    // The plain relMSE against the reference sits above the truth by the reference's noise.
    EXPECT_GT(relMse(image, reference), interval.estimate);
  }
  EXPECT_GE(held, 90);
}

TEST(ErrorInterval, NarrowsAsTheReferenceGetsMoreSamples) {
  const FrameImage truth = test_support::smoothTruth(kPictureSize, kPictureSize);
  double previous = std::numeric_limits<double>::infinity();
  for (const int spp : {16, 64, 256, 1024}) {
    double width = 0;
    for (uint64_t trial = 0; trial < 8; ++trial) {
      const FrameImage image = test_support::noisyCopy(truth, kPictureSigma, 100 + trial, false);
      const FrameImage reference = test_support::noisyCopy(truth, referenceSigma(spp), 200 + trial, true);
      const Interval interval = meanInterval(errorTerms(&image, reference));
      width += interval.high - interval.low;
    }
    EXPECT_LT(width, previous) << spp << " spp";
    previous = width;
  }
}

TEST(ErrorInterval, AnErrorTenPercentAbovePtsIsNeverBelowItAndAThirdBelowIsSeen) {
  const FrameImage truth = test_support::smoothTruth(kPictureSize, kPictureSize);
  int resolvedBetter = 0, heldTheExpectedRatio = 0;
  for (uint64_t trial = 0; trial < 100; ++trial) {
    const FrameImage reference = test_support::noisyCopy(truth, referenceSigma(1024), 3 * trial + 1, true);
    const FrameImage pt = test_support::noisyCopy(truth, kPictureSigma, 3 * trial + 2, false);
    const BlockedTerms ptTerms = errorTerms(&pt, reference);
    // Squared errors 1.1 times pt's: 10 % worse.
    const FrameImage worse = test_support::noisyCopy(truth, kPictureSigma * std::sqrt(1.1), 3 * trial + 3, false);
    const Interval worseRatio = ratioInterval(errorTerms(&worse, reference), ptTerms);
    EXPECT_GE(worseRatio.high, 1.0) << "trial " << trial;
    if (worseRatio.contains(1.1)) ++heldTheExpectedRatio;
    // Squared errors 0.67 times pt's: the interval should tell.
    const FrameImage better = test_support::noisyCopy(truth, kPictureSigma * std::sqrt(0.67), 3 * trial + 3, false);
    if (ratioInterval(errorTerms(&better, reference), ptTerms).high < 1) ++resolvedBetter;
  }
  EXPECT_GE(resolvedBetter, 95);
  EXPECT_GE(heldTheExpectedRatio, 90);
}

TEST(ErrorInterval, ARatioOverAnErrorThatCannotBeToldFromZeroIsUnbounded) {
  const FrameImage truth = test_support::smoothTruth(kPictureSize, kPictureSize);
  int unresolved = 0;
  for (uint64_t trial = 0; trial < 20; ++trial) {
    const FrameImage reference = test_support::noisyCopy(truth, referenceSigma(16), 2 * trial + 1, true);
    const FrameImage image = test_support::noisyCopy(truth, kPictureSigma, 2 * trial + 2, false);
    // The truth itself: its error is 0, which a noisy reference estimates a little above or
    // below 0.
    const BlockedTerms zero = errorTerms(&truth, reference);
    if (meanInterval(zero).low > 0) continue;
    ++unresolved;
    EXPECT_TRUE(std::isinf(ratioInterval(errorTerms(&image, reference), zero).high)) << "trial " << trial;
  }
  EXPECT_GE(unresolved, 15);
  const FrameImage reference = test_support::noisyCopy(truth, referenceSigma(16), 1, true);
  EXPECT_THROW(ratioInterval(errorTerms(&truth, reference), BlockedTerms{}), std::invalid_argument);
}

}  // namespace
}  // namespace pathfarm
