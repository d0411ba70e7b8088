// Piecewise-constant densities against hand-computed answers.
#include <gtest/gtest.h>

#include "renderer/sampling/piecewise_constant.h"

namespace pathfarm {
namespace {

// Values 1, 0, 3 on thirds of [0, 1): the cdf is 0, 1/4, 1/4, 1, the densities 3/4, 0, 9/4.
TEST(PiecewiseConstant1D, InvertsTheCdfAndSkipsEmptyIntervals) {
  const PiecewiseConstant1D d({1, 0, 3});
  EXPECT_FLOAT_EQ(d.integral(), 4.0f / 3);
  const auto first = d.sample(0.125f);
  EXPECT_EQ(first.interval, 0);
  EXPECT_FLOAT_EQ(first.x, 1.0f / 6);
  EXPECT_FLOAT_EQ(first.pdf, 0.75f);
  const auto second = d.sample(0.25f);  // the empty interval's cdf step: the next one
  EXPECT_EQ(second.interval, 2);
  EXPECT_FLOAT_EQ(second.x, 2.0f / 3);
  EXPECT_FLOAT_EQ(second.pdf, 2.25f);
  EXPECT_FLOAT_EQ(d.sample(0.625f).x, 5.0f / 6);
  EXPECT_LT(d.sample(0x1.fffffep-1f).x, 1.0f);
  EXPECT_EQ(d.pdf(1), 0);
}

TEST(PiecewiseConstant1D, AllZeroIsUniformWithZeroDensity) {
  const PiecewiseConstant1D d({0, 0});
  EXPECT_FLOAT_EQ(d.sample(0.75f).x, 0.75f);
  EXPECT_EQ(d.sample(0.75f).pdf, 0);
}

// Rows (1, 1) and (0, 6): the second row is chosen with probability 3/4, then its second
// column always; the density over the unit square is value / mean = value / 2.
TEST(PiecewiseConstant2D, MarginalThenConditional) {
  const PiecewiseConstant2D d({1, 1, 0, 6}, 2, 2);
  EXPECT_FLOAT_EQ(d.integral(), 2);
  const auto s = d.sample({0.3f, 0.5f});
  EXPECT_EQ(s.row, 1);
  EXPECT_EQ(s.column, 1);
  EXPECT_FLOAT_EQ(s.pdf, 3);
  EXPECT_FLOAT_EQ(s.point.y, 0.5f + 0.5f * (0.5f - 0.25f) / 0.75f);
  EXPECT_FLOAT_EQ(d.pdf(0, 0), 0.5f);
  EXPECT_FLOAT_EQ(d.pdf(0, 1), 0);
  const auto top = d.sample({0.75f, 0.125f});
  EXPECT_EQ(top.row, 0);
  EXPECT_FLOAT_EQ(top.point.x, 0.75f);
  EXPECT_FLOAT_EQ(top.point.y, 0.25f);
}

}  // namespace
}  // namespace pathfarm
