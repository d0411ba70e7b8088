#include <gtest/gtest.h>

#include "postproc/metrics/relmse.h"

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

}  // namespace
}  // namespace pathfarm
