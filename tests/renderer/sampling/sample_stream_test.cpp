#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>
#include <vector>

#include "renderer/sampling/sample_stream.h"

namespace pathfarm {
namespace {

TEST(SampleStream, SameKeySameNumbers) {
  SampleStream a({1, 5, 10, 20, 3}), b({1, 5, 10, 20, 3});
  for (int i = 0; i < 100; ++i) EXPECT_EQ(a.nextUint(), b.nextUint());
}

TEST(SampleStream, APixelsStreamsAreItsKeysStreams) {
  // The renderers draw a pixel's streams through PixelStreams, the replays and tests by
  // key: both must give one sample the same numbers.
  for (const SampleKey& key : {SampleKey{1, 5, 10, 20, 0}, SampleKey{7, -3, 0, 179, 255},
                               SampleKey{~0ull, 1'000'000, 1919, 1079, (1u << 31) + 17}}) {
    SampleStream byKey(key), byPixel = PixelStreams(key.sceneSeed, key.frame, key.x, key.y).stream(key.sampleIndex);
    for (int i = 0; i < 20; ++i) EXPECT_EQ(byKey.nextUint(), byPixel.nextUint());
  }
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

// The samples [first, first + count) of one pixel's stratified camera samples, as points
// (film x, film y, time).
std::vector<std::array<float, 3>> cameraSamples(const SampleKey& pixel, uint32_t first, uint32_t count) {
  std::vector<std::array<float, 3>> points;
  const StratifiedPixel pattern(pixel.sceneSeed, pixel.frame, pixel.x, pixel.y);
  for (uint32_t i = first; i < first + count; ++i) {
    const StratifiedSample s = pattern.sample(i);
    points.push_back({s.film.x, s.film.y, s.time});
  }
  return points;
}

// How many of the points fall in each elementary box with 2^bits[d] equal intervals along
// dimension d (only the dimensions with bits[d] >= 0 count; the others are ignored).
std::map<std::vector<int>, int> boxCounts(const std::vector<std::array<float, 3>>& points, std::array<int, 3> bits) {
  std::map<std::vector<int>, int> counts;
  for (const auto& p : points) {
    std::vector<int> box;
    for (size_t d = 0; d < 3; ++d)
      if (bits[d] >= 0) box.push_back(static_cast<int>(std::floor(p[d] * static_cast<float>(1 << bits[d]))));
    ++counts[box];
  }
  return counts;
}

// Every box of the partition holds exactly `each` points (the boxes number 2^(sum of bits)).
void expectEveryBoxHolds(const std::vector<std::array<float, 3>>& points, std::array<int, 3> bits, int each) {
  int boxes = 1;
  for (int b : bits)
    if (b > 0) boxes <<= b;
  const auto counts = boxCounts(points, bits);
  EXPECT_EQ(static_cast<int>(counts.size()), boxes) << bits[0] << " " << bits[1] << " " << bits[2];
  for (const auto& [box, count] : counts) EXPECT_EQ(count, each) << bits[0] << " " << bits[1] << " " << bits[2];
}

TEST(StratifiedPixel, EveryAlignedPowerOfTwoBlockIsANetInPositionAndTime) {
  // The first three dimensions of Sobol's sequence form a (1, 3)-sequence in base 2, and
  // a digit scramble keeps that: any 2^m samples starting at a multiple of 2^m hold
  // exactly 2 points in every elementary box of volume 2^(1 - m), and the film position
  // alone, a (0, 2)-sequence, exactly 1 in every elementary rectangle of area 2^-m.
  const SampleKey pixel{3, 7, 120, 45, 0};
  for (const auto& [first, m] : std::vector<std::pair<uint32_t, int>>{{0, 4}, {0, 6}, {64, 6}, {3 * 256, 8}}) {
    const auto points = cameraSamples(pixel, first, 1u << m);
    for (const auto& p : points)
      for (float v : p) {
        ASSERT_GE(v, 0.0f);
        ASSERT_LT(v, 1.0f);
      }
    for (int a = 0; a <= m; ++a) {
      expectEveryBoxHolds(points, {a, m - a, -1}, 1);
      for (int b = 0; a + b <= m - 1; ++b) expectEveryBoxHolds(points, {a, b, m - 1 - a - b}, 2);
    }
  }
}

TEST(StratifiedPixel, ABlockOfSampleIndicesFarAwayDrawsPositionsOfItsOwn) {
  // A reference renders the same pixels from sample index 2^31 on, so that its samples
  // are independent of the frame's: in no dimension may one of its first 64 coordinates
  // repeat one of the frame's 64 (to the float's 24 bits; by chance, about 1 in 4000).
  const SampleKey pixel{3, 7, 120, 45, 0};
  const auto frame = cameraSamples(pixel, 0, 64), reference = cameraSamples(pixel, 1u << 31, 64);
  for (size_t d = 0; d < 3; ++d) {
    std::set<float> frames;
    for (const auto& point : frame) frames.insert(point[d]);
    for (const auto& point : reference) EXPECT_EQ(frames.count(point[d]), 0u) << "dimension " << d;
  }
  // Within a block, the pattern is one sequence: the block's later samples continue it.
  expectEveryBoxHolds(cameraSamples(pixel, (1u << 31) + 64, 64), {3, 3, -1}, 1);
}

// The 24 bits of a coordinate in [0, 1) as StratifiedPixel makes it.
uint32_t coordinateBits(float v) { return static_cast<uint32_t>(v * 0x1p24f); }

TEST(StratifiedPixel, ThePositionsAreSobolsFirstTwoDimensionsUpToTheScramble) {
  // Within a block, a pixel's scramble is one XOR per dimension, so two samples' film
  // coordinates differ by the XOR of their Sobol points. Sobol's first dimension is the
  // index's bits reversed (van der Corput); the second's generator matrix is Pascal's
  // triangle mod 2: bit r (from the top) of direction number j is C(j, r) mod 2, which by
  // Lucas's theorem is set when r's bits are a subset of j's. Checked for indices over the
  // whole block of 2^24, whose bits the sampler reads a byte at a time.
  const StratifiedPixel pattern(3, 7, 120, 45);
  const StratifiedSample origin = pattern.sample(0);
  const auto sobolSecond = [](uint32_t index) {
    uint32_t bits = 0;
    for (uint32_t j = 0; j < 24; ++j) {
      if (((index >> j) & 1u) == 0) continue;
      for (uint32_t r = 0; r <= j; ++r)
        if ((r & ~j) == 0) bits ^= 1u << (23 - r);
    }
    return bits;
  };
  uint32_t index = 1;
  for (int n = 0; n < 2000; ++n, index = (index * 2654435761u + 12345u) & 0xffffffu) {
    uint32_t reversed = 0;
    for (int j = 0; j < 24; ++j) reversed |= ((index >> j) & 1u) << (23 - j);
    const StratifiedSample s = pattern.sample(index);
    ASSERT_EQ(coordinateBits(s.film.x) ^ coordinateBits(origin.film.x), reversed) << "index " << index;
    ASSERT_EQ(coordinateBits(s.film.y) ^ coordinateBits(origin.film.y), sobolSecond(index)) << "index " << index;
  }
}

TEST(StratifiedPixel, NeighbouringPixelsAndFramesHaveUnrelatedPatterns) {
  std::set<std::array<float, 3>> firsts;
  for (const SampleKey& key : {SampleKey{1, 5, 10, 20, 0}, SampleKey{1, 5, 11, 20, 0}, SampleKey{1, 5, 10, 21, 0},
                               SampleKey{1, 6, 10, 20, 0}, SampleKey{2, 5, 10, 20, 0}}) {
    const StratifiedSample s = StratifiedPixel(key.sceneSeed, key.frame, key.x, key.y).sample(key.sampleIndex);
    firsts.insert({s.film.x, s.film.y, s.time});
  }
  EXPECT_EQ(firsts.size(), 5u);
}

// The root-mean-square error, over 400 pixels, of the share of the pixel and shutter
// that `covered` marks, estimated from 64 stratified camera samples; and the error 64
// independent samples would have, sqrt(p (1 - p) / 64). The true share p is taken on a
// fine grid of 200^3 midpoints.
template <class Covered>
std::pair<double, double> coverageErrors(Covered covered) {
  double truth = 0;
  constexpr int kGrid = 200;
  for (int i = 0; i < kGrid; ++i)
    for (int j = 0; j < kGrid; ++j)
      for (int k = 0; k < kGrid; ++k) truth += covered((i + 0.5f) / kGrid, (j + 0.5f) / kGrid, (k + 0.5f) / kGrid);
  truth /= static_cast<double>(kGrid) * kGrid * kGrid;
  double squaredError = 0;
  constexpr int kPixels = 400, kSamples = 64;
  for (int x = 0; x < kPixels; ++x) {
    double share = 0;
    for (const auto& p : cameraSamples({9, 2, x, 3, 0}, 0, kSamples)) share += covered(p[0], p[1], p[2]);
    share /= kSamples;
    squaredError += (share - truth) * (share - truth);
  }
  return {std::sqrt(squaredError / kPixels), std::sqrt(truth * (1 - truth) / kSamples)};
}

TEST(StratifiedPixel, EdgesAreCoveredFarMoreEvenlyThanByIndependentSamples) {
  // Stratified samples estimate a region bounded by an edge with an error that falls
  // faster than independent samples' N^(-1/2): about N^(-3/4) in two dimensions and
  // N^(-2/3) in three, which at N = 64 is a third and a half of the independent error.
  const auto still = coverageErrors([](float x, float y, float) { return x + 0.4f * y < 0.7f ? 1.0 : 0.0; });
  EXPECT_LT(still.first, still.second / 3) << "still edge: rms " << still.first << ", independent " << still.second;
  const auto moving =
      coverageErrors([](float x, float y, float t) { return x + 0.4f * y + 0.5f * t < 0.9f ? 1.0 : 0.0; });
  EXPECT_LT(moving.first, moving.second / 2) << "moving edge: rms " << moving.first << ", independent "
                                             << moving.second;
}

}  // namespace
}  // namespace pathfarm
