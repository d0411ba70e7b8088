#include <gtest/gtest.h>

#include <set>

#include "renderer/sampling/sample_stream.h"

namespace pathfarm {
namespace {

TEST(SampleStream, SameKeySameNumbers) {
  SampleStream a({1, 5, 10, 20, 3}), b({1, 5, 10, 20, 3});
  for (int i = 0; i < 100; ++i) EXPECT_EQ(a.nextUint(), b.nextUint());
}

TEST(SampleStream, EveryKeyComponentChangesTheStream) {
  const SampleKey base{1, 5, 10, 20, 3};
  std::set<uint32_t> firsts;
  for (SampleKey key : {base, SampleKey{2, 5, 10, 20, 3}, SampleKey{1, 6, 10, 20, 3},
                        SampleKey{1, 5, 11, 20, 3}, SampleKey{1, 5, 10, 21, 3}, SampleKey{1, 5, 10, 20, 4},
                        SampleKey{1, 5, 20, 10, 3}}) {
    firsts.insert(SampleStream(key).nextUint());
  }
  EXPECT_EQ(firsts.size(), 7u);
}

TEST(SampleStream, UniformNumbersFillTheUnitIntervalEvenly) {
  // Chi-square over 16 bins of 16000 draws pooled from many pixels' streams: a bad seed
  // mix shows as correlation between neighbouring pixels.
  int bins[16] = {};
  const int perStream = 10;
  int total = 0;
  for (int x = 0; x < 40; ++x) {
    for (int s = 0; s < 40; ++s) {
      SampleStream stream({0, 0, x, 0, static_cast<uint32_t>(s)});
      for (int i = 0; i < perStream; ++i) {
        const float u = stream.next1D();
        ASSERT_GE(u, 0.0f);
        ASSERT_LT(u, 1.0f);
        ++bins[static_cast<int>(u * 16)];
        ++total;
      }
    }
  }
  double chi2 = 0;
  const double expected = total / 16.0;
  for (int b : bins) chi2 += (b - expected) * (b - expected) / expected;
  EXPECT_LT(chi2, 37.7);  // the 0.999 quantile of chi-square with 15 degrees of freedom
}

}  // namespace
}  // namespace pathfarm
