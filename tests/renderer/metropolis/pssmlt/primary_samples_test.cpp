// Lazy primary-sample mutations: pending small steps add up to one normal step of
// deviation sigma sqrt(n); large steps give fresh uniform numbers.
#include "renderer/metropolis/pssmlt/primary_samples.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pathfarm {
namespace {

// The wrapped difference b - a, in [-0.5, 0.5).
double wrappedDifference(double a, double b) {
  const double d = b - a;
  return d - std::floor(d + 0.5);
}

TEST(PrimarySamples, PendingSmallStepsAddUpToOneStepOfGrownDeviation) {
  SampleStream random({1, 0, 0, 0, 0});
  const int trials = 4000, pending = 9;
  double sumSquares = 0;
  for (int i = 0; i < trials; ++i) {
    PrimarySamples state;
    const double before = state.get(PrimarySamples::kLight, 3, random);
    PrimarySamples later = state;
    for (int s = 0; s < pending; ++s) later = later.nextStep(false);  // accepted without reading coordinate 3
    const double d = wrappedDifference(before, later.get(PrimarySamples::kLight, 3, random));
    sumSquares += d * d;
  }
  const double expected = PrimarySamples::kSmallStepSigma * PrimarySamples::kSmallStepSigma * pending;
  // The sample variance of 4000 normal draws lies within 10 % of the true one (about 4.5 sd).
  EXPECT_NEAR(sumSquares / trials, expected, 0.1 * expected);
}

TEST(PrimarySamples, LargeStepsGiveFreshUniformNumbers) {
  SampleStream random({2, 0, 0, 0, 0});
  PrimarySamples state;
  state.get(PrimarySamples::kCamera, 0, random);
  const int n = 20000;
  int below = 0;
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    state = state.nextStep(true);
    const double v = state.get(PrimarySamples::kCamera, 0, random);
    ASSERT_GE(v, 0);
    ASSERT_LT(v, 1);
    sum += v;
    below += v < 0.25 ? 1 : 0;
  }
  EXPECT_NEAR(sum / n, 0.5, 5 * std::sqrt(1.0 / 12 / n));
  EXPECT_NEAR(static_cast<double>(below) / n, 0.25, 5 * std::sqrt(0.25 * 0.75 / n));
}

TEST(PrimarySamples, ReadingTwiceGivesTheSameValueAndSetHolds) {
  SampleStream random({3, 0, 0, 0, 0});
  PrimarySamples state;
  const double a = state.get(PrimarySamples::kConnection, 5, random);
  EXPECT_EQ(state.get(PrimarySamples::kConnection, 5, random), a);
  PrimarySamples next = state.nextStep(false);
  next.set(PrimarySamples::kCamera, 0, 0.75, random);
  EXPECT_EQ(next.get(PrimarySamples::kCamera, 0, random), 0.75);
  next.set(PrimarySamples::kCamera, 1, 1.25, random);  // wraps
  EXPECT_EQ(next.get(PrimarySamples::kCamera, 1, random), 0.25);
}

}  // namespace
}  // namespace pathfarm
