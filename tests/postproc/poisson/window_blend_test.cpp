// Windows over arbitrary sequence lengths, and the blend between them.
#include "postproc/poisson/window_blend.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "poisson_test_support.h"

namespace pathfarm {
namespace {

TEST(PoissonWindows, CoverEverySequenceLength) {
  for (size_t frames = 1; frames <= 40; ++frames) {
    const auto windows = planWindows(frames, 10, 5);
    std::vector<int> covered(frames, 0);
    for (const PoissonWindow& w : windows) {
      EXPECT_EQ(w.count, std::min<size_t>(10, frames));
      ASSERT_LE(w.first + w.count, frames);
      for (size_t f = w.first; f < w.first + w.count; ++f) ++covered[f];
    }
    for (size_t f = 0; f < frames; ++f) EXPECT_GE(covered[f], 1) << frames << " frames, frame " << f;
    for (size_t i = 1; i < windows.size(); ++i) EXPECT_GE(windows[i - 1].first + 10 - windows[i].first, 5u);
  }
  EXPECT_EQ(planWindows(20, 10, 5).size(), 3u);
  EXPECT_THROW(planWindows(20, 5, 5), std::invalid_argument);
  EXPECT_THROW(planWindows(20, 0, 0), std::invalid_argument);
  for (size_t i = 0; i < 10; ++i) EXPECT_GT(hannWeight(i, 10), 0.0f);
  EXPECT_FLOAT_EQ(hannWeight(2, 10), hannWeight(7, 10));
}

// A static scene: every frame has the same clean image, and noisy primal and spatial
// differences of its own; the temporal differences are exact (zero).
std::vector<GradientFrame> staticSequence(int w, int h, size_t frames, float noise) {
  const poisson_test::Image clean = [](int c, int x, int y) {
    return 0.5f + 0.1f * static_cast<float>(c) + 0.02f * static_cast<float>(x * y % 5);
  };
  std::vector<GradientFrame> sequence;
  for (size_t f = 0; f < frames; ++f) {
    sequence.push_back(poisson_test::exactFrame(w, h, clean, &clean, 0));
    poisson_test::addZeroMeanNoise(sequence.back().primal, noise, static_cast<uint32_t>(3 * f));
    poisson_test::addZeroMeanNoise(sequence.back().gradientX, noise, static_cast<uint32_t>(3 * f + 1));
    poisson_test::addZeroMeanNoise(sequence.back().gradientY, noise, static_cast<uint32_t>(3 * f + 2));
    // Shift each frame's mean so that windows solved alone would disagree on it.
    for (auto& plane : sequence.back().primal)
      for (float& v : plane) v += noise * (f % 2 ? 1.0f : -1.0f);
  }
  return sequence;
}

double meanAbsDifference(const GradientFrame::Color& a, const GradientFrame::Color& b) {
  double sum = 0;
  for (size_t c = 0; c < 3; ++c)
    for (size_t p = 0; p < a[c].size(); ++p) sum += std::abs(a[c][p] - b[c][p]);
  return sum / static_cast<double>(3 * a[0].size());
}

TEST(PoissonWindows, BlendedWindowsShowNoSeam) {
  const int w = 12, h = 10;
  const size_t frames = 14, window = 4, overlap = 2;
  const float noise = 0.1f;
  const auto sequence = staticSequence(w, h, frames, noise);
  std::map<size_t, GradientFrame::Color> blended;
  reconstructSequence(
      frames, [&](size_t f) { return sequence[f]; },
      [&](size_t f, const GradientFrame::Color& color) {
        EXPECT_FALSE(blended.count(f)) << "frame " << f << " delivered twice";
        blended[f] = color;
      },
      window, overlap, PoissonSettings{});
  ASSERT_EQ(blended.size(), frames);
  // Frame-to-frame change anywhere, window boundaries included, stays below the noise.
  double worstBlended = 0;
  for (size_t f = 0; f + 1 < frames; ++f)
    worstBlended = std::max(worstBlended, meanAbsDifference(blended[f], blended[f + 1]));
  EXPECT_LE(worstBlended, noise / 4);

  // Windows cut hard apart (no overlap, no blend) jump at their boundaries: the blend is
  // what removes the seam.
  std::vector<GradientFrame::Color> cut;
  for (size_t first = 0; first < frames; first += window) {
    std::vector<const GradientFrame*> inputs;
    for (size_t f = first; f < std::min(frames, first + window); ++f) inputs.push_back(&sequence[f]);
    for (auto& color : reconstructWindow(inputs, PoissonSettings{})) cut.push_back(std::move(color));
  }
  double worstCut = 0;
  for (size_t f = window - 1; f + 1 < frames; f += window)
    worstCut = std::max(worstCut, meanAbsDifference(cut[f], cut[f + 1]));
  EXPECT_GT(worstCut, 2 * worstBlended);
}

}  // namespace
}  // namespace pathfarm
