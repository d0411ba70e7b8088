// Joint NL-means: every weight term against hand-computed values, the box-filtered patch
// distance against a naive patch loop, and denoising quality on a synthetic image.
#include "postproc/filters/nlmeans.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <limits>
#include <random>

#include "postproc/metrics/relmse.h"

namespace pathfarm {
namespace {

Planes planeOf(int w, int h, const std::vector<float>& values) {
  Planes planes(w, h, 1);
  planes.channels[0] = values;
  return planes;
}

Planes constant(int w, int h, int channels, float value) {
  Planes planes(w, h, channels);
  for (auto& plane : planes.channels) std::fill(plane.begin(), plane.end(), value);
  return planes;
}

NlMeansInput singleFrame(Planes color, Planes variance) {
  NlMeansInput input;
  NlMeansFrame& frame = input.frames.emplace_back();
  frame.color = std::move(color);
  frame.variance = std::move(variance);
  return input;
}

void expectRelative(float actual, double expected, double tolerance, const std::string& what) {
  EXPECT_NEAR(actual, expected, tolerance * std::max(1e-30, std::abs(expected))) << what;
}

// 3x3, one channel: u = 1..9, Var = 0.1..0.9 (row-major).
NlMeansInput ramp3x3() {
  return singleFrame(planeOf(3, 3, {1, 2, 3, 4, 5, 6, 7, 8, 9}),
                     planeOf(3, 3, {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f, 0.7f, 0.8f, 0.9f}));
}

TEST(NlMeansWeights, ColorTermMatchesHandComputedValues) {
  NlMeansSettings s;
  s.patch = 0;  // a single pixel: the per-pixel term itself
  {
    // p = (0,0), q = (1,0): ((1-2)^2 - 4 (0.1 + min(0.1, 0.2))) / (1e-10 + 0.45^2 (0.1 + 0.2))
    //                      = 0.2 / 0.06075 = 3.2921811, w = e^-3.2921811 = 0.0371727
    const NlMeansPairTerms t = jointNlMeansPairTerms(ramp3x3(), s, 0, 1, 0);
    expectRelative(t.colorDistance[0], 3.2921811, 1e-6, "d(0,0 -> 1,0)");
    expectRelative(t.weight[0], 0.0371727, 1e-5, "w(0,0 -> 1,0)");
    // p = (0,1), q = (1,1): u 4 vs 5, Var 0.4 vs 0.5: (1 - 4 * 0.8) / (0.2025 * 0.9) = -12.071331: w = 1
    expectRelative(t.colorDistance[3], -12.071331, 1e-6, "d(0,1 -> 1,1)");
    EXPECT_EQ(t.weight[3], 1.0f);
    // The right column has no partner inside the image.
    EXPECT_EQ(t.weight[2], 0.0f);
    EXPECT_TRUE(std::isinf(t.colorDistance[2]));
  }
  {
    // The term is not symmetric: p = (1,0), q = (0,0): (1 - 4 (0.2 + 0.1)) / 0.06075 = -3.2921811.
    const NlMeansPairTerms t = jointNlMeansPairTerms(ramp3x3(), s, 0, -1, 0);
    expectRelative(t.colorDistance[1], -3.2921811, 1e-6, "d(1,0 -> 0,0)");
    EXPECT_EQ(t.weight[1], 1.0f);
  }
  {
    // p = (0,0), q = (0,1): (9 - 4 * 0.2) / (0.2025 * 0.5) = 80.987654, w = 6.72e-36.
    const NlMeansPairTerms t = jointNlMeansPairTerms(ramp3x3(), s, 0, 0, 1);
    expectRelative(t.colorDistance[0], 80.987654, 1e-6, "d(0,0 -> 0,1)");
    expectRelative(t.weight[0], std::exp(-80.987654), 1e-4, "w(0,0 -> 0,1)");
  }
  {
    // alpha = 1: (1 - 0.2) / 0.06075 = 13.168724, w = 1.909395e-6.
    NlMeansSettings one = s;
    one.alpha = 1.0f;
    const NlMeansPairTerms t = jointNlMeansPairTerms(ramp3x3(), one, 0, 1, 0);
    expectRelative(t.colorDistance[0], 13.168724, 1e-6, "alpha = 1");
    expectRelative(t.weight[0], 1.909395e-6, 1e-5, "alpha = 1 weight");
  }
  {
    // Channels are averaged: a second channel equal in p and q with zero variance adds
    // (0 - 0) / 1e-10 = 0, halving the distance: 3.2921811 / 2.
    NlMeansInput input = ramp3x3();
    input.frames[0].color.channels.push_back(std::vector<float>(9, 2.0f));
    input.frames[0].variance.channels.push_back(std::vector<float>(9, 0.0f));
    const NlMeansPairTerms t = jointNlMeansPairTerms(input, s, 0, 1, 0);
    expectRelative(t.colorDistance[0], 3.2921811 / 2, 1e-6, "two channels");
  }
}

TEST(NlMeansWeights, PatchDistanceAveragesThePixelsInsideBothPatches) {
  NlMeansSettings s;
  s.patch = 1;
  // p = (0,0), q = (1,0): the 3x3 patches overlap the image in (0..1, 0..1) around p and
  // (1..2, 0..1) around q: four pixel pairs, (0,0)-(1,0), (1,0)-(2,0), (0,1)-(1,1), (1,1)-(2,1).
  // d = (1 - 4 (Vp + min(Vp, Vq))) / (0.2025 (Vp + Vq)):
  //   (0.1, 0.2): 0.2 / 0.06075 = 3.2921811     (0.2, 0.3): -0.6 / 0.10125 = -5.9259259
  //   (0.4, 0.5): -2.2 / 0.18225 = -12.071331   (0.5, 0.6): -3.0 / 0.22275 = -13.468013
  // mean: -7.0432722.
  const NlMeansPairTerms t = jointNlMeansPairTerms(ramp3x3(), s, 0, 1, 0);
  expectRelative(t.colorDistance[0], -7.0432722, 1e-6, "patch at a corner");
  EXPECT_EQ(t.weight[0], 1.0f);
}

TEST(NlMeansWeights, FeatureTermsMatchHandComputedValues) {
  // Constant color without variance: d_c = 0, w_c = 1, so the weight is the feature's.
  NlMeansInput input = singleFrame(constant(3, 3, 1, 0.5f), constant(3, 3, 1, 0.0f));
  // A ramp g = 0.1 x: central gradient 0.1 inside (|grad|^2 = 0.01), 0.05 at the left and
  // right columns (edge-clamped neighbours).
  input.frames[0].features.push_back(planeOf(3, 3, {0, 0.1f, 0.2f, 0, 0.1f, 0.2f, 0, 0.1f, 0.2f}));
  input.featureKinds.push_back(FeatureKind::Continuous);
  // An object id: 1 1 2 in every row.
  input.frames[0].features.push_back(planeOf(3, 3, {1, 1, 2, 1, 1, 2, 1, 1, 2}));
  input.featureKinds.push_back(FeatureKind::ExactMatch);
  NlMeansSettings s;
  s.patch = 1;

  const NlMeansPairTerms right = jointNlMeansPairTerms(input, s, 0, 1, 0);
  // p = (1,1), q = (2,1): 0.01 / (0.6^2 max(0.001, 0, 0.01)) = 2.7777778; but the ids differ.
  expectRelative(right.featureDistance[0][4], 2.7777778, 1e-6, "ramp inside");
  EXPECT_TRUE(std::isinf(right.featureDistance[1][4]));
  EXPECT_EQ(right.weight[4], 0.0f);
  // p = (0,1), q = (1,1): 0.01 / (0.36 * 0.0025) = 11.111111; ids equal: w = e^-11.111111.
  expectRelative(right.featureDistance[0][3], 11.111111, 1e-6, "ramp at the border");
  EXPECT_EQ(right.featureDistance[1][3], 0.0f);
  expectRelative(right.weight[3], 1.4945339e-5, 1e-5, "border weight");
  EXPECT_EQ(right.colorDistance[3], 0.0f);

  const NlMeansPairTerms left = jointNlMeansPairTerms(input, s, 0, -1, 0);
  // p = (1,1), q = (0,1): ids equal, w = e^-2.7777778 = 0.0621765.
  expectRelative(left.weight[4], 0.0621765, 1e-5, "w = w_f");

  // With a feature variance of 0.002: (0.01 - (0.002 + 0.002)) / (0.36 max(0.001, 0.002, 0.01))
  // = 1.6666667, w = 0.1888756.
  input.frames[0].featureVariance = {constant(3, 3, 1, 0.002f), Planes()};
  const NlMeansPairTerms withVariance = jointNlMeansPairTerms(input, s, 0, -1, 0);
  expectRelative(withVariance.featureDistance[0][4], 1.6666667, 1e-6, "feature variance");
  expectRelative(withVariance.weight[4], 0.1888756, 1e-5, "feature variance weight");
  // A variance beyond the squared difference cancels it: (0.01 - 0.04) / ... < 0, w = 1.
  input.frames[0].featureVariance = {constant(3, 3, 1, 0.02f), Planes()};
  EXPECT_EQ(jointNlMeansPairTerms(input, s, 0, -1, 0).weight[4], 1.0f);

  // A feature's channels are averaged: a second, constant channel halves both the squared
  // difference and the gradient term, leaving 2.7777778.
  input.frames[0].featureVariance.clear();
  input.frames[0].features[0].channels.push_back(std::vector<float>(9, 0.3f));
  expectRelative(jointNlMeansPairTerms(input, s, 0, -1, 0).featureDistance[0][4], 2.7777778, 1e-6, "two channels");
}

TEST(NlMeansWeights, WeightIsTheMinimumOfColorAndFeatureWeights) {
  NlMeansInput input = ramp3x3();
  input.frames[0].features.push_back(planeOf(3, 3, {0, 0.1f, 0.2f, 0, 0.1f, 0.2f, 0, 0.1f, 0.2f}));
  input.featureKinds.push_back(FeatureKind::Continuous);
  NlMeansSettings s;
  s.patch = 0;
  const NlMeansPairTerms t = jointNlMeansPairTerms(input, s, 0, 1, 0);
  // p = (0,0): d_c = 3.2921811, d_f = 11.111111 (border): w = e^-11.111111.
  expectRelative(t.weight[0], std::exp(-11.111111), 1e-5, "feature dominates");
  // p = (1,0): d_c = (1 - 4 * 0.4) / (0.2025 * 0.5) < 0, d_f = 2.7777778: w = e^-2.7777778.
  expectRelative(t.weight[1], 0.0621765, 1e-5, "feature dominates again");
  s.kf = 100.0f;  // features irrelevant: the color weight e^-3.2921811 remains
  expectRelative(jointNlMeansPairTerms(input, s, 0, 1, 0).weight[0], 0.0371727, 1e-5, "color dominates");
}

// Patch distances by the definition: a loop over the patch, in double.
double naivePatchDistance(const NlMeansInput& input, const NlMeansSettings& s, int t, int px, int py, int dx, int dy) {
  const NlMeansFrame& a = input.frames[0];
  const NlMeansFrame& b = input.frames[static_cast<size_t>(t)];
  const int w = a.color.width, h = a.color.height;
  const auto usable = [](const NlMeansFrame& f, int x, int y) {
    const size_t i = static_cast<size_t>(y * f.color.width + x);
    if (!f.valid.empty() && f.valid[i] == 0.0f) return false;
    for (size_t c = 0; c < f.color.channels.size(); ++c)
      if (!std::isfinite(f.color.channels[c][i]) || !std::isfinite(f.variance.channels[c][i])) return false;
    return true;
  };
  double sum = 0;
  int count = 0;
  for (int sy = -s.patch; sy <= s.patch; ++sy) {
    for (int sx = -s.patch; sx <= s.patch; ++sx) {
      const int ax = px + sx, ay = py + sy, bx = ax + dx, by = ay + dy;
      if (ax < 0 || ay < 0 || ax >= w || ay >= h || bx < 0 || by < 0 || bx >= w || by >= h) continue;
      if (!usable(a, ax, ay) || !usable(b, bx, by)) continue;
      const size_t i = static_cast<size_t>(ay * w + ax), j = static_cast<size_t>(by * w + bx);
      double d = 0;
      for (size_t c = 0; c < a.color.channels.size(); ++c) {
        const double diff = static_cast<double>(a.color.channels[c][i]) - b.color.channels[c][j];
        const double vp = a.variance.channels[c][i], vq = b.variance.channels[c][j];
        d += (diff * diff - s.alpha * (vp + std::min(vp, vq))) / (1e-10 + static_cast<double>(s.kc) * s.kc * (vp + vq));
      }
      sum += d / static_cast<double>(a.color.channels.size());
      ++count;
    }
  }
  return count > 0 ? sum / count : 0.0;
}

NlMeansFrame randomFrame(int w, int h, std::mt19937& rng) {
  std::uniform_real_distribution<float> value(0.0f, 1.0f), variance(0.01f, 0.1f);
  NlMeansFrame frame;
  frame.color = Planes(w, h, 3);
  frame.variance = Planes(w, h, 3);
  for (int c = 0; c < 3; ++c) {
    for (auto& v : frame.color.channels[static_cast<size_t>(c)]) v = value(rng);
    for (auto& v : frame.variance.channels[static_cast<size_t>(c)]) v = variance(rng);
  }
  return frame;
}

TEST(NlMeansWeights, BoxFilteredPatchDistanceEqualsTheNaivePatchLoop) {
  std::mt19937 rng(7);
  const int w = 37, h = 41;  // more than one band of rows
  NlMeansInput input;
  input.frames.push_back(randomFrame(w, h, rng));
  input.frames.push_back(randomFrame(w, h, rng));
  // A broken pixel in frame 0 and invalid pixels in frame 1 drop out of the patches.
  input.frames[0].color.channels[1][static_cast<size_t>(5 * w + 6)] = std::numeric_limits<float>::quiet_NaN();
  input.frames[1].valid.assign(static_cast<size_t>(w * h), 1.0f);
  for (int i = 0; i < w * h; i += 7) input.frames[1].valid[static_cast<size_t>(i)] = 0.0f;
  for (int f : {0, 1, 3}) {
    NlMeansSettings s;
    s.patch = f;
    for (int t : {0, 1}) {
      for (auto [dx, dy] : {std::pair{0, 0}, {1, 0}, {3, -2}, {-5, 4}, {-36, 7}, {2, 33}}) {
        const NlMeansPairTerms terms = jointNlMeansPairTerms(input, s, t, dx, dy);
        for (int y = 0; y < h; ++y) {
          for (int x = 0; x < w; ++x) {
            const float fast = terms.colorDistance[static_cast<size_t>(y * w + x)];
            if (x + dx < 0 || x + dx >= w || y + dy < 0 || y + dy >= h) {
              ASSERT_TRUE(std::isinf(fast));
              continue;
            }
            const double naive = naivePatchDistance(input, s, t, x, y, dx, dy);
            ASSERT_NEAR(fast, naive, 1e-5 * std::max(1.0, std::abs(naive)))
                << "f " << f << " frame " << t << " offset " << dx << "," << dy << " pixel " << x << "," << y;
          }
        }
      }
    }
  }
}

TEST(NlMeans, CenterAloneGivesTheInputBack) {
  std::mt19937 rng(3);
  NlMeansInput input;
  input.frames.push_back(randomFrame(20, 9, rng));
  NlMeansSettings s;
  s.radius = 0;
  const Planes out = jointNlMeans(input, s);
  EXPECT_EQ(out.channels, input.frames[0].color.channels);
  EXPECT_EQ(jointNlMeansPairTerms(input, s, 0, 0, 0).weight, std::vector<float>(180, 1.0f));
}

TEST(NlMeans, SameBitsForAnyThreadCount) {
  std::mt19937 rng(11);
  NlMeansInput input;
  input.frames.push_back(randomFrame(70, 100, rng));
  input.frames.push_back(randomFrame(70, 100, rng));
  input.frames[0].features.push_back(randomFrame(70, 100, rng).color);
  input.featureKinds.push_back(FeatureKind::Continuous);
  input.frames[1].features.push_back(input.frames[0].features[0]);
  NlMeansSettings s;
  s.radius = 4;
  const Planes parallel = jointNlMeans(input, s);
  Planes serial;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    serial = jointNlMeans(input, s);
  }
  EXPECT_EQ(parallel.channels, serial.channels);
}

// A worker with AVX2 and one without must filter to the same bits (nlmeans.cpp): every
// term (colors, both kinds of feature, invalid pixels, several frames) through both.
TEST(NlMeans, SameBitsWithAndWithoutWideVectors) {
  if (!__builtin_cpu_supports("avx2")) GTEST_SKIP() << "this CPU has no AVX2: only one code path runs here";
  std::mt19937 rng(23);
  const int w = 53, h = 70;  // several bands, and rows that are no multiple of a vector
  NlMeansInput input;
  input.featureKinds = {FeatureKind::Continuous, FeatureKind::ExactMatch};
  std::uniform_int_distribution<int> id(0, 2);
  for (int t = 0; t < 3; ++t) {
    NlMeansFrame& frame = input.frames.emplace_back(randomFrame(w, h, rng));
    frame.features.push_back(randomFrame(w, h, rng).color);
    Planes ids(w, h, 1);
    for (float& v : ids.channels[0]) v = static_cast<float>(id(rng));
    frame.features.push_back(std::move(ids));
  }
  input.frames[0].color.channels[2][static_cast<size_t>(3 * w + 9)] = std::numeric_limits<float>::infinity();
  input.frames[1].valid.assign(static_cast<size_t>(w * h), 1.0f);
  for (size_t p = 0; p < input.frames[1].valid.size(); p += 7) input.frames[1].valid[p] = 0.0f;
  for (const bool sparse : {false, true}) {
    NlMeansSettings wide;
    wide.radius = 3;
    wide.validCentersOnly = sparse;
    NlMeansSettings narrow = wide;
    narrow.wideVectors = false;
    NlMeansStats wideStats, narrowStats;
    const Planes a = jointNlMeans(input, wide, &wideStats);
    const Planes b = jointNlMeans(input, narrow, &narrowStats);
    EXPECT_EQ(a.channels, b.channels) << (sparse ? "valid centers only" : "every pixel");
    EXPECT_EQ(wideStats.unfilledCenters, narrowStats.unfilledCenters);
  }
}

// Piecewise-smooth ground truth with a sharp edge at x = w/2, present in a feature.
struct Synthetic {
  int w = 96, h = 64;
  std::vector<float> truth, feature;

  Synthetic() {
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const bool right = x >= w / 2;
        truth.push_back(right ? 1.0f + 0.2f * std::sin(static_cast<float>(y) / 9.0f)
                              : 0.2f + 0.3f * static_cast<float>(x) / w);
        feature.push_back(right ? 0.8f : 0.3f);
      }
    }
  }
  // Mean over rows of the column x.
  static float columnMean(const std::vector<float>& image, int w, int h, int x) {
    double sum = 0;
    for (int y = 0; y < h; ++y) sum += image[static_cast<size_t>(y * w + x)];
    return static_cast<float>(sum / h);
  }
};

TEST(NlMeans, DenoisesASyntheticImageAndKeepsItsFeatureEdge) {
  const Synthetic scene;
  const float sigma = 0.15f;
  std::mt19937 rng(2024);
  std::normal_distribution<float> noise(0.0f, sigma);
  std::vector<float> noisy = scene.truth;
  for (float& v : noisy) v += noise(rng);
  NlMeansInput input = singleFrame(planeOf(scene.w, scene.h, noisy), constant(scene.w, scene.h, 1, sigma * sigma));
  input.frames[0].features.push_back(planeOf(scene.w, scene.h, scene.feature));
  input.featureKinds.push_back(FeatureKind::Continuous);
  NlMeansSettings s;
  s.radius = 10;
  const Planes out = jointNlMeans(input, s);

  const double before = relMse(noisy, scene.truth), after = relMse(out.channels[0], scene.truth);
  EXPECT_LT(after * 4, before) << "relMSE " << before << " -> " << after;
  const int edge = scene.w / 2;
  const float truthContrast = Synthetic::columnMean(scene.truth, scene.w, scene.h, edge) -
                              Synthetic::columnMean(scene.truth, scene.w, scene.h, edge - 1);
  const float contrast = Synthetic::columnMean(out.channels[0], scene.w, scene.h, edge) -
                         Synthetic::columnMean(out.channels[0], scene.w, scene.h, edge - 1);
  EXPECT_NEAR(contrast, truthContrast, 0.1f * truthContrast);

  // Without the feature the filter still denoises, relying on the color alone.
  input.frames[0].features.clear();
  input.featureKinds.clear();
  EXPECT_LT(relMse(jointNlMeans(input, s).channels[0], scene.truth), before);
}

TEST(NlMeans, BrokenPixelsAreFilledFromTheirNeighboursAndCounted) {
  const Synthetic scene;
  std::vector<float> color = scene.truth, variance(color.size(), 0.01f);
  color[100] = std::numeric_limits<float>::quiet_NaN();
  color[2000] = std::numeric_limits<float>::infinity();
  variance[3000] = std::numeric_limits<float>::quiet_NaN();
  variance[3001] = -1.0f;  // counts as 0
  NlMeansInput input = singleFrame(planeOf(scene.w, scene.h, color), planeOf(scene.w, scene.h, variance));
  input.frames[0].features.push_back(planeOf(scene.w, scene.h, scene.feature));
  input.featureKinds.push_back(FeatureKind::Continuous);
  NlMeansStats stats;
  const Planes out = jointNlMeans(input, NlMeansSettings{}, &stats);
  EXPECT_EQ(stats.invalidCenters, 3u);
  EXPECT_EQ(stats.unfilledCenters, 0u);
  for (size_t p = 0; p < out.pixelCount(); ++p) ASSERT_TRUE(std::isfinite(out.channels[0][p])) << p;
  for (size_t p : {100u, 2000u, 3000u}) {
    EXPECT_EQ(stats.invalidCenter[p], 1);
    EXPECT_NEAR(out.channels[0][p], scene.truth[p], 0.05f) << p;
  }
  // A frame of nothing but broken pixels: zeros, all counted, no crash.
  NlMeansInput broken =
      singleFrame(constant(4, 4, 3, std::numeric_limits<float>::quiet_NaN()), constant(4, 4, 3, 1.0f));
  const Planes zeros = jointNlMeans(broken, NlMeansSettings{}, &stats);
  EXPECT_EQ(stats.invalidCenters, 16u);
  EXPECT_EQ(stats.unfilledCenters, 16u);
  EXPECT_EQ(zeros.channels[0], std::vector<float>(16, 0.0f));
}

TEST(NlMeans, RefusesMismatchedInput) {
  NlMeansInput input = singleFrame(constant(4, 4, 3, 1.0f), constant(4, 3, 3, 1.0f));
  EXPECT_THROW(jointNlMeans(input, NlMeansSettings{}), std::invalid_argument);
  input = singleFrame(constant(4, 4, 3, 1.0f), constant(4, 4, 2, 1.0f));
  EXPECT_THROW(jointNlMeans(input, NlMeansSettings{}), std::invalid_argument);
  input = singleFrame(constant(4, 4, 3, 1.0f), constant(4, 4, 3, 1.0f));
  input.frames[0].features.push_back(constant(4, 4, 1, 0.0f));  // no kind for it
  EXPECT_THROW(jointNlMeans(input, NlMeansSettings{}), std::invalid_argument);
  input.featureKinds.push_back(FeatureKind::Continuous);
  input.frames.push_back(input.frames[0]);
  input.frames[1].valid.assign(3, 1.0f);
  EXPECT_THROW(jointNlMeans(input, NlMeansSettings{}), std::invalid_argument);
  input.frames[1].valid.clear();
  EXPECT_NO_THROW(jointNlMeans(input, NlMeansSettings{}));
  EXPECT_THROW(jointNlMeans(NlMeansInput{}, NlMeansSettings{}), std::invalid_argument);
  NlMeansSettings negative;
  negative.radius = -1;
  EXPECT_THROW(jointNlMeans(input, negative), std::invalid_argument);
}

}  // namespace
}  // namespace pathfarm
