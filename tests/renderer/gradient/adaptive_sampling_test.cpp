// Adaptive sampling's density map and sample allocation.
#include "renderer/gradient/adaptive_sampling.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

namespace pathfarm {
namespace {

TEST(AdaptiveSampling, MedianRemovesALoneOutlierAndTheMeanClampsARegion) {
  const int w = 20, h = 16;
  std::vector<float> variance(static_cast<size_t>(w * h), 1.0f);
  variance[static_cast<size_t>(8 * w + 9)] = 1e6f;
  for (float d : samplingDensity(variance, w, h)) EXPECT_NEAR(d, 1.0f, 1e-5f);

  // A 6x6 block far above the rest is clamped to 8 times the mean.
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 6; ++x) variance[static_cast<size_t>(y * w + x)] = 1e4f;
  // The block's smoothed values are about 1e4 and the map's mean about 1e4 * 36 / 320,
  // so 8 times the mean cuts them to a flat top well below 1e4.
  const std::vector<float> density = samplingDensity(variance, w, h);
  const float top = *std::max_element(density.begin(), density.end());
  EXPECT_LT(top, 0.95e4f);
  EXPECT_EQ(density[static_cast<size_t>(2 * w + 2)], top);
  EXPECT_EQ(density[static_cast<size_t>(1 * w + 3)], top);
  EXPECT_NEAR(density[static_cast<size_t>(15 * w + 19)], 1.0f, 1e-5f);
}

TEST(AdaptiveSampling, AllocationSpendsTheBudgetInProportion) {
  const std::vector<float> density{1, 2, 3, 0, 4};
  const auto samples = allocateSamples(density, 100);
  EXPECT_EQ(std::accumulate(samples.begin(), samples.end(), 0u), 100u);
  EXPECT_EQ(samples[3], 0u);
  EXPECT_EQ(samples[4], 40u);
  const auto uniform = allocateSamples(std::vector<float>(4, 0.0f), 10);
  EXPECT_EQ(std::accumulate(uniform.begin(), uniform.end(), 0u), 10u);
  EXPECT_LE(*std::max_element(uniform.begin(), uniform.end()) - *std::min_element(uniform.begin(), uniform.end()), 1u);
}

}  // namespace
}  // namespace pathfarm
