// The chain driver on a toy target whose image is known in closed form: a density
// f(x, y, tau) = (0.5 + x)(0.2 + y^2)(1 + tau / 4) over the unit square times the open
// time of a two-frame window, splatted at pixel (x W, y H) of frame floor(tau).
#include "renderer/metropolis/chain_driver.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace pathfarm {
namespace {

constexpr int kSize = 8;

double toyDensity(double x, double y, double tau) { return (0.5 + x) * (0.2 + y * y) * (1 + tau / 4); }

struct ToyState {
  double x = 0, y = 0, tau = 0;
  Contribution contribution;
};

double wrap(double v) { return v - std::floor(v); }

class ToyTarget {
 public:
  using State = ToyState;
  enum Kind { kLarge, kSmall, kTemporal };

  explicit ToyTarget(const WindowTime& time, float largeStep = 0.3f) : time_(time), largeStep_(largeStep) {}

  int strategies() const { return 1; }
  State bootstrap(int, SampleStream& random) const {
    const double x = random.next1D(), y = random.next1D();
    return at(x, y, time_.fromPrimary(random.next1D()));
  }
  Proposal<State> propose(const State& s, MutationContext& context) const {
    SampleStream& random = context.random;
    const float choice = random.next1D();
    if (choice < largeStep_) return {bootstrap(0, random), kLarge, 1};
    if (choice < largeStep_ + (1 - largeStep_) / 2) {
      const double r = 0.05 * std::sqrt(-2 * std::log(1 - static_cast<double>(random.next1D())));
      const double phi = 2 * M_PI * random.next1D();
      return {at(wrap(s.x + r * std::cos(phi)), wrap(s.y + r * std::sin(phi)), s.tau), kSmall, 1};
    }
    const double tau = context.temporal.sample(s.tau, random.next1D());
    const double forward = context.temporal.density(s.tau, tau);
    return {at(s.x, s.y, tau), kTemporal, forward > 0 ? context.temporal.density(tau, s.tau) / forward : 0};
  }
  std::vector<std::string> mutationKinds() const { return {"large", "small", "temporal"}; }
  int temporalKind() const { return kTemporal; }

 private:
  State at(double x, double y, double tau) const {
    State s{x, y, tau, {}};
    s.contribution.frame = static_cast<int64_t>(std::floor(tau));
    s.contribution.film = {static_cast<float>(x * kSize), static_cast<float>(y * kSize)};
    const double f = time_.isOpen(tau) ? toyDensity(x, y, tau) : 0;
    // Grey, so the luminance (the chain's scalar) is f itself up to rounding.
    s.contribution.value = Rgb(static_cast<float>(f));
    return s;
  }
  const WindowTime& time_;
  float largeStep_;
};

static_assert(ChainTarget<ToyTarget>);

// The toy image: f averaged over pixel (i, j) and frame k's open time [k, k + 0.5).
double analyticPixel(int i, int j, int k, double meanShutterFraction = 0.25) {
  const double y0 = static_cast<double>(j) / kSize, y1 = static_cast<double>(j + 1) / kSize;
  const double meanY2 = (y1 * y1 * y1 - y0 * y0 * y0) / 3 * kSize;
  return (0.5 + (i + 0.5) / kSize) * (0.2 + meanY2) * (1 + (k + meanShutterFraction) / 4);
}

ChainSettings toySettings(double mutationsPerPixel) {
  ChainSettings settings;
  settings.sceneSeed = 17;
  settings.width = settings.height = kSize;
  settings.mutationsPerPixel = mutationsPerPixel;
  settings.bootstrapSamples = 20000;
  settings.chains = 16;
  settings.chainsPerBlock = 4;
  settings.temporalDelta = 0.6;
  return settings;
}

std::vector<FrameImage> renderToy(const ChainSettings& settings, const WindowTime& time, float largeStep = 0.3f) {
  const ToyTarget target(time, largeStep);
  const ChainDriver driver(target, time, settings);
  const SeedPool pool = driver.seedPool();
  std::vector<BlockResult> blocks;
  for (int b = 0; b < settings.blocks(); ++b) blocks.push_back(driver.runBlock(pool, b));
  return mergeBlocks(time.window(), settings.blocks(), std::move(blocks));
}

// Root mean square of the pixels' relative errors, and each frame's mean relative error.
struct ToyErrors {
  double rmsRelative = 0;
  std::vector<double> frameRelative;
};

ToyErrors errorsOf(const std::vector<FrameImage>& frames, double meanShutterFraction = 0.25) {
  ToyErrors errors;
  double sumSquares = 0;
  for (int k = 0; k < static_cast<int>(frames.size()); ++k) {
    double sum = 0, expected = 0;
    for (int j = 0; j < kSize; ++j)
      for (int i = 0; i < kSize; ++i) {
        const double value = frames[static_cast<size_t>(k)].channel("G")[static_cast<size_t>(j * kSize + i)];
        const double truth = analyticPixel(i, j, k, meanShutterFraction);
        sumSquares += (value - truth) * (value - truth) / (truth * truth);
        sum += value;
        expected += truth;
      }
    errors.frameRelative.push_back(sum / expected - 1);
  }
  errors.rmsRelative = std::sqrt(sumSquares / (kSize * kSize * static_cast<double>(frames.size())));
  return errors;
}

// The toy normalization's mean and its standard deviation per bootstrap sample, from fine
// midpoint sums over x, y and the open time.
struct ToyMoments {
  double mean = 0, deviation = 0;
};

ToyMoments toyMoments(const WindowTime& time) {
  double mean = 0, meanSquare = 0;
  const int n = 200;
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b)
      for (int c = 0; c < 20; ++c) {
        const double f = toyDensity((a + 0.5) / n, (b + 0.5) / n, time.fromPrimary((c + 0.5) / 20));
        mean += f;
        meanSquare += f * f;
      }
  mean /= n * n * 20.0;
  meanSquare /= n * n * 20.0;
  return {mean, std::sqrt(meanSquare - mean * mean)};
}

TEST(ChainDriver, NormalizationMatchesTheIntegralWithinItsStandardError) {
  const WindowTime time({0, 2}, 0.0f, 0.5f);
  const ToyTarget target(time);
  const ChainSettings settings = toySettings(10);
  const SeedPool pool = ChainDriver(target, time, settings).seedPool();
  const ToyMoments truth = toyMoments(time);
  EXPECT_NEAR(pool.normalization, truth.mean, 5 * truth.deviation / std::sqrt(static_cast<double>(*settings.bootstrapSamples)));
  EXPECT_EQ(pool.seeds.size(), static_cast<size_t>(settings.chains));
}

TEST(ChainDriver, ABootstrapSizedToTheWindowGrowsWithItsMutationsAndNarrowsTheNormalization) {
  const WindowTime time({0, 2}, 0.0f, 0.5f);
  ChainSettings small = toySettings(64), large = toySettings(320000);
  small.bootstrapSamples = large.bootstrapSamples = std::nullopt;
  // 8 x 8 pixels and 2 frames: 8,192 and 40,960,000 mutations.
  EXPECT_EQ(small.bootstrapSamplesOf(time.window()), kMinimumBootstrapSamples);
  EXPECT_EQ(large.bootstrapSamplesOf(time.window()), 40960000 / kMutationsPerBootstrapSample);
  ChainSettings given = large;
  given.bootstrapSamples = 123;
  EXPECT_EQ(given.bootstrapSamplesOf(time.window()), 123u);

  // Over independent seeds, the normalization's spread is the one a mean of that many
  // samples has (the bounds hold a 24-seed estimate with probability above 0.999), so
  // the larger window's is a quarter of the smaller one's: 160,000 samples against 10,000.
  const ToyTarget target(time);
  const ToyMoments truth = toyMoments(time);
  for (ChainSettings settings : {small, large}) {
    double sumSquares = 0;
    const int seeds = 24;
    for (int seed = 0; seed < seeds; ++seed) {
      settings.sceneSeed = 1000 + static_cast<uint64_t>(seed);
      const double error = ChainDriver(target, time, settings).seedPool().normalization - truth.mean;
      sumSquares += error * error;
    }
    const double spread = std::sqrt(sumSquares / seeds);
    const double expected = truth.deviation / std::sqrt(static_cast<double>(settings.bootstrapSamplesOf(time.window())));
    EXPECT_GT(spread, 0.55 * expected);
    EXPECT_LT(spread, 1.5 * expected);
  }
}

TEST(ChainDriver, SplattedImageConvergesToTheAnalyticDensity) {
  const WindowTime time({0, 2}, 0.0f, 0.5f);
  const ToyErrors coarse = errorsOf(renderToy(toySettings(250), time));
  const ToyErrors fine = errorsOf(renderToy(toySettings(1000), time));
  // A pixel gets about 1000 mutations' splats at the finer budget. Independent samples
  // would give a relative error near 1 / sqrt(1000); allow for correlation along the
  // chains as if only every 10th mutation were independent, and 4 standard deviations.
  const double independent = 1 / std::sqrt(1000.0);
  EXPECT_LT(fine.rmsRelative, 4 * std::sqrt(10.0) * independent);
  EXPECT_LT(fine.rmsRelative, 0.75 * coarse.rmsRelative);  // 4x the mutations: about half
  // Each frame's total (the temporal mutation's share of the work): 64x the samples.
  for (double e : fine.frameRelative) EXPECT_LT(std::abs(e), 4 * std::sqrt(10.0) * independent / 8);
}

// Short shutters and a reach of several frames make the temporal proposal strongly
// asymmetric (the open time in reach differs from frame to frame); with hardly any large
// steps, each frame's share of the light is right only if the reverse density enters the
// acceptance.
TEST(ChainDriver, TemporalMutationsKeepEachFramesShare) {
  const WindowTime time({0, 3}, 0.0f, 0.2f);
  ChainSettings settings = toySettings(4000);
  settings.temporalDelta = 1.5;
  const ToyErrors errors = errorsOf(renderToy(settings, time, 0.02f), 0.1);
  // 256k mutations per frame; counting only every 50th as independent (large steps are
  // rare here) leaves 5000, a relative spread near 1 / sqrt(5000) = 0.014 of a frame's
  // total at most: 0.03 is beyond 2 of those and far below the 15-30 % that dropping
  // the reverse density causes.
  for (double e : errors.frameRelative) EXPECT_LT(std::abs(e), 0.03);
}

TEST(ChainDriver, MergedBitsDoNotDependOnTheSplitIntoTasksOrThreads) {
  const WindowTime time({3, 2}, 0.25f, 1.0f);
  ChainSettings settings = toySettings(40);
  settings.tuneDelta = true;
  settings.threads = 1;
  const std::vector<FrameImage> oneTask = renderToy(settings, time);

  // Four "processes": each parses the pool from text and runs one block with 2 threads.
  settings.threads = 2;
  const ToyTarget target(time);
  const std::string poolText = ChainDriver(target, time, settings).seedPool().serialize();
  std::vector<BlockResult> blocks;
  for (int b = 3; b >= 0; --b) {
    const ToyTarget ownTarget(time);
    blocks.push_back(ChainDriver(ownTarget, time, settings).runBlock(SeedPool::parse(poolText), b));
  }
  const std::vector<FrameImage> fourTasks = mergeBlocks(time.window(), 4, std::move(blocks));
  ASSERT_EQ(oneTask.size(), fourTasks.size());
  for (size_t f = 0; f < oneTask.size(); ++f)
    for (const char* c : {"R", "G", "B"}) EXPECT_EQ(oneTask[f].channel(c), fourTasks[f].channel(c));
  for (const char* key : {"pathfarm.mlt.mutations", "pathfarm.mlt.acceptance.temporal", "pathfarm.mlt.final_delta"})
    EXPECT_EQ(oneTask[0].attributes().at(key), fourTasks[0].attributes().at(key)) << key;
}

TEST(ChainDriver, TuningMovesTheTemporalAcceptanceTowardsTheTarget) {
  const WindowTime time({0, 8}, 0.0f, 0.5f);
  const ToyTarget target(time);
  ChainSettings settings = toySettings(40);
  settings.temporalDelta = 0.02;  // tiny steps: almost every one is accepted
  settings.tuningShare = 0.5;
  const ChainDriver fixed(target, time, settings);
  const MutationStats untuned = fixed.runBlock(fixed.seedPool(), 0).stats;
  settings.tuneDelta = true;
  const ChainDriver tuning(target, time, settings);
  const MutationStats tuned = tuning.runBlock(tuning.seedPool(), 0).stats;
  // Acceptance far above the target: the tuned reach grows, the fixed one stays.
  EXPECT_GT(untuned.temporalAcceptance(), 0.8);
  EXPECT_EQ(untuned.meanFinalDelta(), settings.temporalDelta);
  EXPECT_GT(tuned.meanFinalDelta(), 2 * settings.temporalDelta);
  EXPECT_LT(tuned.temporalAcceptance(), untuned.temporalAcceptance());
}

// With an acceptance of exp(-D) the rule settles where exp(-D) = 0.23, and stops at the
// end of the tuning part.
TEST(DeltaTuner, SettlesWhereTheAcceptanceMeetsTheTarget) {
  DeltaTuner tuner(0.1, 8, true, 0.23, 20000);
  for (uint64_t m = 0; m < 20000; ++m) tuner.observe(m, std::exp(-tuner.delta()));
  EXPECT_NEAR(tuner.delta(), -std::log(0.23), 0.05);
  const double settled = tuner.delta();
  tuner.observe(20000, 1.0);
  EXPECT_EQ(tuner.delta(), settled);
  DeltaTuner off(0.1, 8, false, 0.23, 20000);
  off.observe(0, 1.0);
  EXPECT_EQ(off.delta(), 0.1);
}

TEST(ChainDriver, MergeRejectsMissingOrRepeatedBlocks) {
  const WindowTime time({0, 1}, 0.0f, 1.0f);
  const ToyTarget target(time);
  const ChainDriver driver(target, time, toySettings(4));
  const SeedPool pool = driver.seedPool();
  std::vector<BlockResult> blocks{driver.runBlock(pool, 0), driver.runBlock(pool, 0), driver.runBlock(pool, 2),
                                  driver.runBlock(pool, 3)};
  EXPECT_THROW(mergeBlocks(time.window(), 4, blocks), std::invalid_argument);
  blocks.pop_back();
  EXPECT_THROW(mergeBlocks(time.window(), 4, blocks), std::invalid_argument);
  EXPECT_THROW(driver.runBlock(pool, 4), std::invalid_argument);
  SeedPool other = pool;
  other.window.first = 1;
  EXPECT_THROW(driver.runBlock(other, 0), std::invalid_argument);
}

TEST(SeedPool, TextRoundTripsExactly) {
  SeedPool pool;
  pool.window = {-4, 3};
  pool.bootstrapSamples = 12345;
  pool.normalization = 0.1 + 1e-17;
  pool.seeds = {{7, 2, 1.0 / 3}, {99, 0, 2.5e-9}};
  const SeedPool back = SeedPool::parse(pool.serialize());
  EXPECT_EQ(back.window.first, -4);
  EXPECT_EQ(back.window.count, 3);
  EXPECT_EQ(back.bootstrapSamples, 12345u);
  EXPECT_EQ(back.normalization, pool.normalization);
  ASSERT_EQ(back.seeds.size(), 2u);
  EXPECT_EQ(back.seeds[1].bootstrapIndex, 99u);
  EXPECT_EQ(back.seeds[0].strategy, 2);
  EXPECT_EQ(back.seeds[0].contribution, 1.0 / 3);
  EXPECT_THROW(SeedPool::parse("nonsense"), std::invalid_argument);
  EXPECT_THROW(SeedPool::parse(pool.serialize() + "extra"), std::invalid_argument);
}

}  // namespace
}  // namespace pathfarm
