#include "postproc/filters/guided_upsample.h"

#include <gtest/gtest.h>

#include "test_support.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <vector>

namespace pathfarm {
namespace {

Planes makePlanes(int width, int height, int count, const std::function<float(int, int, int)>& value) {
  Planes planes(width, height, count);
  for (int c = 0; c < count; ++c)
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) planes.channels[static_cast<size_t>(c)][static_cast<size_t>(y) * width + x] =
          value(c, x, y);
  return planes;
}

float at(const Planes& planes, int c, int x, int y) {
  return planes.channels[static_cast<size_t>(c)][static_cast<size_t>(y) * planes.width + x];
}

using test_support::hashed;

// The guided filter straight from He et al.'s equations: every window's statistics summed
// directly, (Sigma + eps U) a = cov solved by Gaussian elimination, coefficients averaged
// directly. No clamping of negative results.
Planes bruteForce(const Planes& low, const Planes& guide, int factor, int radius, double epsilon) {
  const int W = guide.width, H = guide.height, R = radius * factor;
  const int n = static_cast<int>(guide.channels.size()), m = static_cast<int>(low.channels.size());
  const auto I = [&](int c, int x, int y) { return static_cast<double>(at(guide, c, x, y)); };
  const auto p = [&](int j, int x, int y) { return static_cast<double>(at(low, j, x / factor, y / factor)); };
  std::vector<std::vector<double>> a(static_cast<size_t>(W * H), std::vector<double>(static_cast<size_t>(n * m)));
  std::vector<std::vector<double>> b(static_cast<size_t>(W * H), std::vector<double>(static_cast<size_t>(m)));
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      std::vector<double> meanI(static_cast<size_t>(n)), meanP(static_cast<size_t>(m));
      std::vector<double> II(static_cast<size_t>(n * n)), Ip(static_cast<size_t>(n * m));
      int count = 0;
      for (int v = std::max(0, y - R); v <= std::min(H - 1, y + R); ++v)
        for (int u = std::max(0, x - R); u <= std::min(W - 1, x + R); ++u) {
          ++count;
          for (int c = 0; c < n; ++c) {
            meanI[c] += I(c, u, v);
            for (int d = 0; d < n; ++d) II[c * n + d] += I(c, u, v) * I(d, u, v);
            for (int j = 0; j < m; ++j) Ip[c * m + j] += I(c, u, v) * p(j, u, v);
          }
          for (int j = 0; j < m; ++j) meanP[j] += p(j, u, v);
        }
      for (double& v : meanI) v /= count;
      for (double& v : meanP) v /= count;
      // Augmented system [Sigma + eps U | cov].
      std::vector<double> A(static_cast<size_t>(n * (n + m)));
      for (int c = 0; c < n; ++c) {
        for (int d = 0; d < n; ++d) A[c * (n + m) + d] = II[c * n + d] / count - meanI[c] * meanI[d] + (c == d ? epsilon : 0);
        for (int j = 0; j < m; ++j) A[c * (n + m) + n + j] = Ip[c * m + j] / count - meanI[c] * meanP[j];
      }
      for (int col = 0; col < n; ++col) {
        int pivot = col;
        for (int r = col + 1; r < n; ++r)
          if (std::abs(A[r * (n + m) + col]) > std::abs(A[pivot * (n + m) + col])) pivot = r;
        for (int k = 0; k < n + m; ++k) std::swap(A[col * (n + m) + k], A[pivot * (n + m) + k]);
        for (int r = 0; r < n; ++r) {
          if (r == col) continue;
          const double f = A[r * (n + m) + col] / A[col * (n + m) + col];
          for (int k = 0; k < n + m; ++k) A[r * (n + m) + k] -= f * A[col * (n + m) + k];
        }
      }
      const size_t i = static_cast<size_t>(y) * W + x;
      for (int j = 0; j < m; ++j) {
        b[i][j] = meanP[j];
        for (int c = 0; c < n; ++c) {
          a[i][c * m + j] = A[c * (n + m) + n + j] / A[c * (n + m) + c];
          b[i][j] -= a[i][c * m + j] * meanI[c];
        }
      }
    }
  Planes q(W, H, m);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      for (int j = 0; j < m; ++j) {
        double sum = 0;
        int count = 0;
        for (int v = std::max(0, y - R); v <= std::min(H - 1, y + R); ++v)
          for (int u = std::max(0, x - R); u <= std::min(W - 1, x + R); ++u) {
            const size_t k = static_cast<size_t>(v) * W + u;
            ++count;
            sum += b[k][j];
            for (int c = 0; c < n; ++c) sum += a[k][c * m + j] * I(c, x, y);
          }
        q.channels[static_cast<size_t>(j)][static_cast<size_t>(y) * W + x] = static_cast<float>(sum / count);
      }
  return q;
}

GuidedUpsampleSettings settingsOf(int factor, int radius, float epsilon, int threads = 0) {
  GuidedUpsampleSettings settings;
  settings.factor = factor;
  settings.radius = radius;
  settings.epsilon = epsilon;
  settings.threads = threads;
  return settings;
}

TEST(GuidedUpsample, MatchesTheGuidedFilterComputedByBruteForce) {
  struct Case {
    int lowWidth, lowHeight, factor, radius, guideChannels, inputChannels;
    float epsilon;
  };
  const Case cases[] = {
      {7, 5, 3, 1, 2, 2, 1e-2f},   // factor 3
      {9, 40, 2, 2, 4, 1, 1e-3f},  // 80 rows: several strips
      {4, 3, 2, 5, 3, 3, 1e-3f},   // windows larger than the image
      {6, 6, 1, 1, 1, 3, 1e-4f},   // factor 1: the plain guided filter
      {5, 4, 2, 0, 3, 2, 1e-3f},   // radius 0: 1-pixel windows
  };
  for (const Case& t : cases) {
    const int W = t.lowWidth * t.factor, H = t.lowHeight * t.factor;
    const Planes low = makePlanes(t.lowWidth, t.lowHeight, t.inputChannels,
                                  [](int c, int x, int y) { return 0.2f + hashed(1, c, x, y); });
    const Planes guide = makePlanes(W, H, t.guideChannels, [](int c, int x, int y) {
      return 0.3f * hashed(2, c, x, y) + 0.5f * std::sin(0.3f * x + 0.2f * y * (c + 1));
    });
    const GuidedUpsampleResult result = guidedUpsample(low, guide, settingsOf(t.factor, t.radius, t.epsilon));
    const Planes expected = bruteForce(low, guide, t.factor, t.radius, t.epsilon);
    ASSERT_EQ(result.image.width, W);
    ASSERT_EQ(result.image.height, H);
    ASSERT_EQ(result.image.channels.size(), static_cast<size_t>(t.inputChannels));
    size_t negative = 0;
    for (size_t i = 0; i < expected.pixelCount(); ++i) {
      bool anyNegative = false;
      for (int j = 0; j < t.inputChannels; ++j) {
        const float want = expected.channels[static_cast<size_t>(j)][i];
        if (want < 0) anyNegative = true;
        ASSERT_NEAR(result.image.channels[static_cast<size_t>(j)][i], std::max(want, 0.0f), 2e-5f)
            << "pixel " << i << " channel " << j << " (factor " << t.factor << ", radius " << t.radius << ")";
      }
      negative += anyNegative ? 1 : 0;
    }
    EXPECT_EQ(result.negativePixels, negative);
  }
}

TEST(GuidedUpsample, ConstantInputStaysConstant) {
  const Planes low = makePlanes(16, 12, 3, [](int c, int, int) { return 0.25f + 0.5f * c; });
  const Planes guide = makePlanes(64, 48, 5, [](int c, int x, int y) { return hashed(7, c, x, y) * (c + 1); });
  const GuidedUpsampleResult result = guidedUpsample(low, guide, settingsOf(4, 2, 1e-4f));
  EXPECT_EQ(result.negativePixels, 0u);
  for (int c = 0; c < 3; ++c)
    for (const float v : result.image.channels[static_cast<size_t>(c)]) ASSERT_NEAR(v, 0.25f + 0.5f * c, 1e-6f);
  for (const float flag : result.rerender) ASSERT_EQ(flag, 0.0f);
}

// Regions on the low-resolution grid (so their edges fall between low-resolution pixels):
// background 0, a disk 1, a rectangle 2 and a diagonal band 3, which meet and overlap.
int regionAt(int lx, int ly) {
  if ((lx - 8) * (lx - 8) + (ly - 7) * (ly - 7) <= 20) return 1;
  if (lx >= 12 && lx < 20 && ly >= 3 && ly < 10) return 2;
  if (std::abs(lx - ly - 2) <= 1) return 3;
  return 0;
}

TEST(GuidedUpsample, ReproducesAPiecewiseConstantImageWhoseEdgesTheGuideShares) {
  const int factor = 2, lowWidth = 24, lowHeight = 16;
  const float value[4][3] = {{0.1f, 0.5f, 2.0f}, {1.5f, 0.2f, 0.7f}, {0.05f, 3.0f, 0.4f}, {0.8f, 0.8f, 0.0f}};
  const Planes low = makePlanes(lowWidth, lowHeight, 3, [&](int c, int x, int y) { return value[regionAt(x, y)][c]; });
  const auto region = [&](int x, int y) { return regionAt(x / factor, y / factor); };

  // The full-resolution image itself as the guide: 4 affinely independent colors.
  const Planes itself = makePlanes(lowWidth * factor, lowHeight * factor, 3,
                                   [&](int c, int x, int y) { return value[region(x, y)][c]; });
  // A feature with the same edges but other values (a "normal" of 3 channels).
  const float normal[4][3] = {{0, 0, 1}, {0.6f, 0, 0.8f}, {0, -0.6f, 0.8f}, {0.48f, 0.6f, 0.64f}};
  const Planes feature = makePlanes(lowWidth * factor, lowHeight * factor, 3,
                                    [&](int c, int x, int y) { return normal[region(x, y)][c]; });
  for (const Planes* guide : {&itself, &feature})
    for (const int radius : {1, 2}) {
      const GuidedUpsampleResult result = guidedUpsample(low, *guide, settingsOf(factor, radius, 1e-7f));
      EXPECT_EQ(result.negativePixels, 0u);
      for (int y = 0; y < guide->height; ++y)
        for (int x = 0; x < guide->width; ++x)
          for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(at(result.image, c, x, y), value[region(x, y)][c], 1e-4f)
                << "(" << x << ", " << y << ") channel " << c << " radius " << radius;
    }
}

TEST(GuidedUpsample, KeepsAnEdgeThatSplitsALowResolutionPixelSharp) {
  // A vertical edge at x = 13 splits the low-resolution column 6 (factor 2); the input is
  // the box average of the truth, 0.6 in that column. Nearest upsampling has no step
  // between x = 12 and 13 and errs by 0.4 there; the guided filter puts the step where the
  // guide has it and spreads the mixed pixel's error thinly over its windows.
  const int factor = 2, W = 40, H = 16;
  const auto truth = [](int x) { return x < 13 ? 0.2f : 1.0f; };
  const Planes low = makePlanes(W / factor, H / factor, 1, [&](int, int x, int) {
    return 0.5f * (truth(factor * x) + truth(factor * x + 1));
  });
  const Planes guide = makePlanes(W, H, 1, [&](int, int x, int) { return truth(x); });
  const GuidedUpsampleResult result = guidedUpsample(low, guide, settingsOf(factor, 2, 1e-4f));
  for (int y = 0; y < H; ++y) {
    EXPECT_GT(at(result.image, 0, 13, y) - at(result.image, 0, 12, y), 0.5f);
    for (int x = 0; x < W; ++x) {
      EXPECT_LT(std::abs(at(result.image, 0, x, y) - truth(x)), 0.15f) << x;
      if (x > 0) {
        EXPECT_GE(at(result.image, 0, x, y), at(result.image, 0, x - 1, y)) << x;  // monotone
      }
    }
  }
}

TEST(GuidedUpsample, FlagsCountsAndZeroesNegativeInput) {
  // Channel 1 is -0.5 on the left half and +0.5 on the right; channel 0 is 1 everywhere.
  const Planes low = makePlanes(10, 6, 2, [](int c, int x, int) { return c == 0 ? 1.0f : (x < 5 ? -0.5f : 0.5f); });
  const Planes guide = makePlanes(20, 12, 1, [](int, int, int) { return 0.5f; });
  const GuidedUpsampleResult result = guidedUpsample(low, guide, settingsOf(2, 1, 1e-3f));
  size_t flagged = 0;
  for (int y = 0; y < 12; ++y)
    for (int x = 0; x < 20; ++x) {
      const float flag = result.rerender[static_cast<size_t>(y) * 20 + x];
      flagged += flag != 0 ? 1 : 0;
      EXPECT_NEAR(at(result.image, 0, x, y), 1.0f, 1e-6f);  // the other channel is kept
      if (flag != 0) {
        EXPECT_EQ(at(result.image, 1, x, y), 0.0f);
      } else {
        EXPECT_GT(at(result.image, 1, x, y), 0.0f);
      }
    }
  // A constant guide: q is the input averaged twice over 5x5 windows, negative left of the
  // middle (x < 10).
  for (int y = 0; y < 12; ++y) {
    EXPECT_EQ(result.rerender[static_cast<size_t>(y) * 20 + 9], 1.0f);
    EXPECT_EQ(result.rerender[static_cast<size_t>(y) * 20 + 10], 0.0f);
  }
  EXPECT_EQ(result.negativePixels, flagged);
  EXPECT_EQ(flagged, 10u * 12u);

  const Planes allNegative = makePlanes(4, 4, 1, [](int, int, int) { return -1.0f; });
  const GuidedUpsampleResult zero = guidedUpsample(allNegative, makePlanes(8, 8, 2, [](int c, int x, int y) { return hashed(5, c, x, y); }), settingsOf(2, 1, 1e-3f));
  EXPECT_EQ(zero.negativePixels, 64u);
  for (const float v : zero.image.channels[0]) EXPECT_EQ(v, 0.0f);
}

TEST(GuidedUpsample, FlagsTheOvershootOfALinearFitAcrossAKink) {
  // The guide is a ramp; the input is 0 left of a kink and rises steeply to its right. The
  // windows straddling the kink fit a line that dips below 0 on their left.
  const int factor = 2, W = 48, H = 8;
  const Planes low = makePlanes(W / factor, H / factor, 1, [](int, int x, int) { return std::max(0.0f, 2.0f * (x - 11)); });
  const Planes guide = makePlanes(W, H, 1, [](int, int x, int) { return 0.05f * x; });
  const GuidedUpsampleResult result = guidedUpsample(low, guide, settingsOf(factor, 2, 1e-4f));
  const Planes unclamped = bruteForce(low, guide, factor, 2, 1e-4);
  EXPECT_GT(result.negativePixels, 0u);
  size_t flagged = 0;
  for (size_t i = 0; i < unclamped.pixelCount(); ++i) {
    const float want = unclamped.channels[0][i];
    const float flag = result.rerender[i];
    flagged += flag != 0 ? 1 : 0;
    if (want < -1e-5f) {
      EXPECT_EQ(flag, 1.0f) << "pixel " << i << " should be flagged (" << want << ")";
    }
    if (want > 1e-5f) {
      EXPECT_EQ(flag, 0.0f) << "pixel " << i;
    }
    if (flag != 0) {
      EXPECT_EQ(result.image.channels[0][i], 0.0f);
    } else {
      EXPECT_GE(result.image.channels[0][i], 0.0f);
    }
  }
  EXPECT_EQ(result.negativePixels, flagged);
}

TEST(GuidedUpsample, IsDeterministicWhateverTheThreadCount) {
  const Planes low = makePlanes(50, 75, 3, [](int c, int x, int y) { return hashed(3, c, x, y); });
  const Planes guide = makePlanes(100, 150, 9, [](int c, int x, int y) { return hashed(4, c, x, y); });
  const GuidedUpsampleResult one = guidedUpsample(low, guide, settingsOf(2, 2, 1e-3f, 1));
  const GuidedUpsampleResult three = guidedUpsample(low, guide, settingsOf(2, 2, 1e-3f, 3));
  const GuidedUpsampleResult all = guidedUpsample(low, guide, settingsOf(2, 2, 1e-3f, 0));
  EXPECT_EQ(one.image.channels, three.image.channels);
  EXPECT_EQ(one.image.channels, all.image.channels);
  EXPECT_EQ(one.rerender, three.rerender);
}

// Rows first .. end - 1 of every plane (of a plane `factor` times smaller, rows / factor).
Planes rowsOf(const Planes& planes, int first, int end, int factor = 1) {
  Planes band(planes.width, (end - first) / factor, 0);
  for (const std::vector<float>& channel : planes.channels)
    band.channels.emplace_back(channel.begin() + static_cast<ptrdiff_t>(first / factor) * planes.width,
                               channel.begin() + static_cast<ptrdiff_t>(end / factor) * planes.width);
  return band;
}

TEST(GuidedUpsample, ABandOfRowsGivenTheRowsItReadsIsThoseRowsOfTheWholeFramesBits) {
  const int width = 60, height = 300, factor = 2;
  const Planes low = makePlanes(width / factor, height / factor, 3, [](int c, int x, int y) { return hashed(5, c, x, y); });
  const Planes guide = makePlanes(width, height, 6, [](int c, int x, int y) { return hashed(6, c, x, y); });
  const GuidedUpsampleSettings whole = settingsOf(factor, 2, 1e-3f, 2);
  const GuidedUpsampleResult frame = guidedUpsample(low, guide, whole);
  // Bands at the frame's top and bottom, and one whose borders are not strip borders.
  for (const FrameRows wanted : {FrameRows{0, 37}, FrameRows{101, 177}, FrameRows{250, 300}}) {
    const FrameRows reads = guidedUpsampleReads(wanted, height, whole);
    ASSERT_LE(reads.first, wanted.first);
    ASSERT_GE(reads.end, wanted.end);
    GuidedUpsampleSettings band = whole;
    band.firstRow = reads.first;
    band.onlyFirst = wanted.first;
    band.onlyEnd = wanted.end;
    const GuidedUpsampleResult part =
        guidedUpsample(rowsOf(low, reads.first, reads.end, factor), rowsOf(guide, reads.first, reads.end), band);
    for (size_t c = 0; c < frame.image.channels.size(); ++c)
      for (int y = reads.first; y < reads.end; ++y)
        for (int x = 0; x < width; ++x) {
          const float value = part.image.channels[c][static_cast<size_t>(y - reads.first) * width + x];
          if (y >= wanted.first && y < wanted.end)
            ASSERT_EQ(value, frame.image.channels[c][static_cast<size_t>(y) * width + x])
                << "channel " << c << " at (" << x << ", " << y << ")";
          else
            ASSERT_EQ(value, 0.0f) << "a row outside the band at " << y;
        }
    for (int y = wanted.first; y < wanted.end; ++y)
      for (int x = 0; x < width; ++x) {
        const size_t inBand = static_cast<size_t>(y - reads.first) * width + x, inFrame = static_cast<size_t>(y) * width + x;
        ASSERT_EQ(part.rerender[inBand], frame.rerender[inFrame]);
        ASSERT_EQ(part.deficit[inBand], frame.deficit[inFrame]);
      }
  }
  // Fewer rows than it reads: rows near the band's border come out otherwise.
  const FrameRows wanted{100, 177};
  const FrameRows reads = guidedUpsampleReads(wanted, height, whole);
  GuidedUpsampleSettings band = whole;
  band.firstRow = wanted.first - 2;
  band.onlyFirst = wanted.first;
  band.onlyEnd = wanted.end;
  const GuidedUpsampleResult cut =
      guidedUpsample(rowsOf(low, band.firstRow, reads.end, factor), rowsOf(guide, band.firstRow, reads.end), band);
  const size_t firstPixel = static_cast<size_t>(wanted.first) * width;
  EXPECT_NE(cut.image.channels[0][static_cast<size_t>(2) * width], frame.image.channels[0][firstPixel]);
  // A band outside the planes, or planes starting between low-resolution rows, are refused.
  band.onlyEnd = reads.end + 1;
  EXPECT_THROW(guidedUpsample(rowsOf(low, band.firstRow, reads.end, factor), rowsOf(guide, band.firstRow, reads.end), band),
               std::invalid_argument);
  band.onlyEnd = wanted.end;
  band.onlyFirst = wanted.first + 1;
  band.firstRow = wanted.first + 1;  // odd
  EXPECT_THROW(guidedUpsample(rowsOf(low, 100, reads.end, factor), rowsOf(guide, 100, reads.end), band),
               std::invalid_argument)
      << "a first row between low-resolution rows";
}

TEST(GuidedUpsample, RejectsInputThatDoesNotFit) {
  const Planes low = makePlanes(4, 3, 1, [](int, int, int) { return 1.0f; });
  const Planes guide = makePlanes(8, 6, 2, [](int, int, int) { return 1.0f; });
  EXPECT_NO_THROW(guidedUpsample(low, guide, settingsOf(2, 1, 1e-3f)));
  try {
    guidedUpsample(low, guide, settingsOf(3, 1, 1e-3f));
    FAIL() << "a guide of the wrong size was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("needs a 12x9 guide, not 8x6"), std::string::npos) << e.what();
  }
  EXPECT_THROW(guidedUpsample(low, guide, settingsOf(0, 1, 1e-3f)), std::invalid_argument);
  EXPECT_THROW(guidedUpsample(low, guide, settingsOf(2, -1, 1e-3f)), std::invalid_argument);
  EXPECT_THROW(guidedUpsample(low, guide, settingsOf(2, 1, 0.0f)), std::invalid_argument);
  Planes shortChannel = guide;
  shortChannel.channels[1].pop_back();
  EXPECT_THROW(guidedUpsample(low, shortChannel, settingsOf(2, 1, 1e-3f)), std::invalid_argument);
  EXPECT_THROW(guidedUpsample(low, Planes(8, 6, 0), settingsOf(2, 1, 1e-3f)), std::invalid_argument);
  EXPECT_THROW(guidedUpsample(Planes(4, 3, 0), guide, settingsOf(2, 1, 1e-3f)), std::invalid_argument);
}

}  // namespace
}  // namespace pathfarm
