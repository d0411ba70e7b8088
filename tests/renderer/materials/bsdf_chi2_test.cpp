// Pearson chi-square goodness-of-fit of sample() against pdf(): directions are histogrammed
// on a (theta, phi) grid of the sphere and compared with counts predicted by integrating
// pdf() over each cell. This catches a sampler and a pdf that disagree in shape, which the
// pointwise checks in bsdf_test.cpp cannot (they compare pdf() with itself).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "renderer/materials/bsdf.h"
#include "tests/renderer/materials/bsdf_test_support.h"

namespace pathfarm::bsdftest {
namespace {

constexpr int kThetaBins = 20, kPhiBins = 40;
constexpr int kCells = kThetaBins * kPhiBins;
constexpr int kSamples = 100000;

int cellOf(Vec3f w) {
  const float theta = std::acos(std::clamp(w.z, -1.0f, 1.0f));
  const int i = std::min(kThetaBins - 1, int(theta / kPi * kThetaBins));
  float phi = std::atan2(w.y, w.x);
  if (phi < 0) phi += 2 * kPi;
  const int j = std::min(kPhiBins - 1, int(phi / (2 * kPi) * kPhiBins));
  return i * kPhiBins + j;
}

class BsdfChi2 : public ::testing::TestWithParam<MaterialCase> {};

TEST_P(BsdfChi2, SampleDistributionMatchesPdf) {
  const MaterialCase& c = GetParam();
  const Bsdf bsdf(c.material, c.albedo, kRoughnessThreshold);
  for (const Vec3f wo : testDirections(c.twoSided)) {
    // The last cell collects samples that fail or pick a delta lobe.
    std::vector<double> observed(kCells + 1, 0), expected(kCells + 1, 0);
    Uniform rng(10);
    for (int n = 0; n < kSamples; ++n) {
      const float uLobe = rng.next();
      const auto s = bsdf.sample(wo, uLobe, rng.next2());
      observed[s && !s->delta ? cellOf(s->wi) : kCells] += 1;
    }
    double total = 0;
    for (int i = 0; i < kThetaBins; ++i) {
      for (int j = 0; j < kPhiBins; ++j) {
        // To a fifth of a sample, far below the counts' standard deviation.
        const double p = integrateCell([&](Vec3f wi) { return bsdf.pdf(wo, wi); }, kPi * i / kThetaBins,
                                       kPi * (i + 1) / kThetaBins, 2 * kPi * j / kPhiBins,
                                       2 * kPi * (j + 1) / kPhiBins, 0.2 / kSamples);
        expected[i * kPhiBins + j] = p * kSamples;
        total += expected[i * kPhiBins + j];
      }
    }
    expected.back() = std::max(0.0, kSamples - total);

    // Cells expecting fewer than 5 samples are pooled, as the test's asymptotics require.
    double chi2 = 0, pooledObserved = 0, pooledExpected = 0;
    int cells = 0;
    for (size_t k = 0; k < observed.size(); ++k) {
      if (expected[k] < 5) {
        pooledObserved += observed[k];
        pooledExpected += expected[k];
        continue;
      }
      const double d = observed[k] - expected[k];
      chi2 += d * d / expected[k];
      ++cells;
    }
    if (pooledExpected >= 5) {
      const double d = pooledObserved - pooledExpected;
      chi2 += d * d / pooledExpected;
      ++cells;
    } else {
      EXPECT_LT(pooledObserved, 20) << "samples where pdf() says there are none, wo.z = " << wo.z;
    }
    // Significance 1e-4 (normal quantile 3.719) per direction: with fixed seeds the test is
    // deterministic, and a wrong sampler exceeds this by orders of magnitude.
    const int dof = cells - 1;
    EXPECT_LT(chi2, chiSquareQuantile(dof, 3.719)) << "wo.z = " << wo.z << ", " << dof << " dof";
  }
}

INSTANTIATE_TEST_SUITE_P(Materials, BsdfChi2, ::testing::ValuesIn(nonDeltaCases()), caseName);

}  // namespace
}  // namespace pathfarm::bsdftest
