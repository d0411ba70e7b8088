// Window time and the temporal proposal against analytic measures and independent
// numerical integration of the proposal density.
#include "renderer/metropolis/window_time.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "renderer/metropolis/temporal_proposal.h"

namespace pathfarm {
namespace {

TEST(WindowTime, PrimarySamplesRoundTripAndLandOnOpenTime) {
  const WindowTime time({10, 3}, 0.25f, 0.75f);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> uniform(0, 1);
  for (int i = 0; i < 1000; ++i) {
    const double u = uniform(rng);
    const double tau = time.fromPrimary(u);
    ASSERT_TRUE(time.isOpen(tau)) << tau;
    EXPECT_NEAR(time.toPrimary(tau), u, 1e-12);
  }
  // u = 0.5 of three frames is the middle of the second frame's open time.
  const auto instant = time.instant(time.fromPrimary(0.5));
  ASSERT_TRUE(instant);
  EXPECT_EQ(instant->frame, 11);
  EXPECT_NEAR(instant->shutterFraction, 0.5, 1e-6);
  EXPECT_EQ(time.fromPrimary(0), 10.25);
  EXPECT_LT(time.fromPrimary(std::nextafter(1.0, 0.0)), 12.75);
}

TEST(WindowTime, InstantsGiveFrameAndShutterFraction) {
  const WindowTime time({-2, 4}, 0.2f, 0.6f);
  const auto inside = time.instant(-1 + 0.5);
  ASSERT_TRUE(inside);
  EXPECT_EQ(inside->frame, -1);
  EXPECT_NEAR(inside->shutterFraction, (0.5 - 0.2) / 0.4, 1e-6);
  EXPECT_FALSE(time.instant(-1 + 0.7));  // shutter closed
  EXPECT_FALSE(time.instant(-1 + 0.1));
  EXPECT_FALSE(time.instant(2.3));       // after the window
  EXPECT_FALSE(time.instant(-2.5));      // before it
}

TEST(WindowTime, OpenMeasureMatchesShutterTimesFrames) {
  const WindowTime time({5, 4}, 0.1f, 0.6f);
  EXPECT_NEAR(time.openLength(), 4 * 0.5, 1e-6);
  EXPECT_NEAR(time.openBefore(time.end()), time.openLength(), 1e-9);
  EXPECT_NEAR(time.openBefore(7.35), 2 * 0.5 + 0.25, 1e-6);
  // The share of uniformly drawn times that are open, within 5 standard deviations.
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> uniform(5, 9);
  const int n = 20000;
  int open = 0;
  for (int i = 0; i < n; ++i) open += time.isOpen(uniform(rng)) ? 1 : 0;
  const double p = 0.5;
  EXPECT_NEAR(static_cast<double>(open) / n, p, 5 * std::sqrt(p * (1 - p) / n));
  // The inverses of the cumulative measures land where they claim.
  for (double m : {0.0, 0.3, 1.2, 1.99}) {
    EXPECT_NEAR(time.openBefore(time.atOpenMeasure(m)), m, 1e-9);
    EXPECT_TRUE(time.isOpen(time.atOpenMeasure(m)));
    EXPECT_NEAR(time.closedBefore(time.atClosedMeasure(m)), m, 1e-9);
    EXPECT_FALSE(time.isOpen(time.atClosedMeasure(m)));
  }
}

TEST(WindowTime, ZeroLengthShutterIsAClearError) {
  try {
    const WindowTime time({0, 2}, 0.5f, 0.5f);
    FAIL() << "accepted a shutter of zero length";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("zero length"), std::string::npos) << e.what();
  }
  EXPECT_THROW(WindowTime({0, 0}, 0, 0.5f), std::invalid_argument);
}

// The proposal's density integrated by the midpoint rule over [a, b).
double integrate(const TemporalProposal& proposal, double tau, double a, double b, bool onlyClosed,
                 const WindowTime& time) {
  const int steps = 20000;
  const double h = (b - a) / steps;
  double sum = 0;
  for (int i = 0; i < steps; ++i) {
    const double x = a + (i + 0.5) * h;
    if (!onlyClosed || !time.isOpen(x)) sum += proposal.density(tau, x) * h;
  }
  return sum;
}

TEST(TemporalProposal, PutsTenPercentOnClosedShutterAndIntegratesToOne) {
  const WindowTime time({0, 6}, 0.0f, 0.5f);
  const TemporalProposal proposal(time, 1.3);
  for (double tau : {2.2, 0.1, 5.45}) {  // inside, and cut by either end of the window
    EXPECT_NEAR(integrate(proposal, tau, tau - 1.5, tau + 1.5, false, time), 1, 1e-3) << tau;
    EXPECT_NEAR(integrate(proposal, tau, tau - 1.5, tau + 1.5, true, time), 0.1, 1e-3) << tau;
    EXPECT_EQ(proposal.closedMass(tau), 0.1);
  }
  // By sampling: the share of proposals on closed time, within 5 standard deviations.
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> uniform(0, 1);
  const int n = 20000;
  int closed = 0;
  for (int i = 0; i < n; ++i) closed += time.isOpen(proposal.sample(2.2, uniform(rng))) ? 0 : 1;
  EXPECT_NEAR(static_cast<double>(closed) / n, 0.1, 5 * std::sqrt(0.1 * 0.9 / n));
}

TEST(TemporalProposal, AlwaysOpenShutterProposesOnlyOpenTime) {
  const WindowTime time({0, 3}, 0.0f, 1.0f);
  const TemporalProposal proposal(time, 0.5);
  EXPECT_EQ(proposal.closedMass(1.5), 0);
  EXPECT_NEAR(proposal.density(1.5, 1.2), 1.0, 1e-12);  // uniform over [1, 2)
  EXPECT_NEAR(proposal.density(0.2, 0.5), 1 / 0.7, 1e-12);  // cut to [0, 0.7)
}

TEST(TemporalProposal, DensityVanishesOutsideReachAndWindow) {
  const WindowTime time({0, 4}, 0.1f, 0.7f);
  const TemporalProposal proposal(time, 0.8);
  EXPECT_EQ(proposal.density(2.3, 2.3 + 0.81), 0);
  EXPECT_EQ(proposal.density(2.3, 2.3 - 0.81), 0);
  EXPECT_EQ(proposal.density(0.2, -0.1), 0);
  EXPECT_EQ(proposal.density(3.6, 4.05), 0);
  EXPECT_GT(proposal.density(2.3, 2.9), 0);
  EXPECT_GT(proposal.density(2.3, 2.8), 0);  // closed time in reach
  EXPECT_THROW(TemporalProposal(time, 0), std::invalid_argument);
}

// Chi-square of samples against the density integrated over 40 bins of [tau - D, tau + D].
TEST(TemporalProposal, SamplesFollowTheDensity) {
  const WindowTime time({0, 3}, 0.2f, 0.65f);
  const double tau = 0.9, delta = 1.1;
  const TemporalProposal proposal(time, delta);
  const int bins = 40, n = 40000;
  const double lo = tau - delta, width = 2 * delta / bins;
  std::vector<int> counts(bins, 0);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> uniform(0, 1);
  for (int i = 0; i < n; ++i) {
    const double t = proposal.sample(tau, uniform(rng));
    ASSERT_GT(proposal.density(tau, t), 0) << t;
    ++counts[static_cast<size_t>(std::clamp(static_cast<int>((t - lo) / width), 0, bins - 1))];
  }
  double chi2 = 0;
  int dof = 0;
  for (int b = 0; b < bins; ++b) {
    const double expected = n * integrate(proposal, tau, lo + b * width, lo + (b + 1) * width, false, time);
    if (expected < 5) {
      EXPECT_LE(counts[static_cast<size_t>(b)], 5 + 5 * std::sqrt(5.0)) << b;
      continue;
    }
    chi2 += (counts[static_cast<size_t>(b)] - expected) * (counts[static_cast<size_t>(b)] - expected) / expected;
    ++dof;
  }
  // Far beyond the 99.99th percentile of chi-square (mean dof, sd sqrt(2 dof)).
  EXPECT_LT(chi2, dof + 6 * std::sqrt(2.0 * dof)) << dof;
}

}  // namespace
}  // namespace pathfarm
