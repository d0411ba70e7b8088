// The irradiance flow solved in bands of rows (postproc/interpolation/irradiance_flow.h):
// the bands' layout, rows computed alone being the whole frame's bits while reading only
// their bands' rows, the flow of a known translation recovered across band borders and
// trusted, flows whose two directions disagree left to the primary motion, and bands
// without the component left invalid.
#include "postproc/interpolation/irradiance_flow.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace pathfarm {
namespace {

constexpr int kBandedWidth = 48, kBandedHeight = 200;
constexpr float kBandedShiftX = 2.4f, kBandedShiftY = 6.6f;  // keyframe 1 is keyframe 0 moved by this
const FlowBanding kBanding{64, 16};              // four bands of 50 rows

// A smooth, positive texture (the flow matches its log).
float bandedTexture(float x, float y) {
  return 1.0f + 0.6f * std::sin(0.7f * x + 0.3f * y) * std::cos(0.45f * y - 0.2f * x) +
         0.3f * std::sin(0.23f * x * 0.5f + 0.61f * y);
}

// A keyframe's component, made on demand a band at a time, recording the rows asked for.
struct SyntheticKeyframe {
  float shiftX = 0.0f, shiftY = 0.0f;  // its texture is moved by this
  float motionX = 0.0f, motionY = 0.0f;  // its primary motion towards the other keyframe
  int emptyEnd = 0;                      // rows [0, emptyEnd) hold no irradiance
  std::vector<std::pair<int, int>> rowsRead, irradianceRead;

  float value(int x, int y) const {
    return bandedTexture(static_cast<float>(x) - shiftX, static_cast<float>(y) - shiftY);
  }

  Planes irradiance(int first, int end) const {
      Planes planes(kBandedWidth, end - first, 3);
      for (int y = first; y < end; ++y)
        for (int x = 0; x < kBandedWidth; ++x)
          for (int c = 0; c < 3; ++c)
            planes.channels[static_cast<size_t>(c)][static_cast<size_t>((y - first) * kBandedWidth + x)] =
                y < emptyEnd ? 0.0f : (0.5f + 0.25f * static_cast<float>(c)) * value(x, y);
      return planes;
  }

  ComponentRows rows() {
    ComponentRows rows{kBandedWidth, kBandedHeight, {}, {}};
    rows.rows = [this](int first, int end) {
      rowsRead.emplace_back(first, end);
      const size_t pixels = static_cast<size_t>(kBandedWidth * (end - first));
      MotionField field{kBandedWidth, end - first, std::vector<float>(pixels, motionX), std::vector<float>(pixels, motionY), {}};
      field.top = first;
      field.frameHeight = kBandedHeight;
      return ComponentBand{irradiance(first, end), std::move(field)};
    };
    rows.irradiance = [this](int first, int end) {
      irradianceRead.emplace_back(first, end);
      return irradiance(first, end);
    };
    return rows;
  }
};

// Keyframe 0 and keyframe 1 = keyframe 0 moved by the shift; the primary motion is the
// shift rounded (the flow finds the rest).
std::pair<SyntheticKeyframe, SyntheticKeyframe> translatedPair() {
  return {SyntheticKeyframe{0.0f, 0.0f, 2.0f, 7.0f}, SyntheticKeyframe{kBandedShiftX, kBandedShiftY, -2.0f, -7.0f}};
}

TEST(IrradianceFlow, BandsCoverTheFrameOnceWithTheirHalo) {
  for (const int height : {1, 180, 512, 513, 1080, 1100, 2160}) {
    const std::vector<FlowBand> bands = flowBandsOf(height);
    ASSERT_FALSE(bands.empty());
    EXPECT_EQ(bands.size(), static_cast<size_t>((height + 511) / 512)) << height;
    int next = 0;
    for (const FlowBand& band : bands) {
      EXPECT_EQ(band.first, next);
      EXPECT_EQ(band.first % 2, 0) << "as the filter windows' borders";
      EXPECT_LE(band.end - band.first, 512);
      EXPECT_LE(std::abs((band.end - band.first) - (bands.front().end - bands.front().first)), 2);
      EXPECT_EQ(band.haloFirst, std::max(0, band.first - 128));
      EXPECT_EQ(band.haloEnd, std::min(height, band.end + 128));
      next = band.end;
    }
    EXPECT_EQ(next, height);
  }
  EXPECT_EQ(flowBandsOf(1080, {0, 0}).size(), 1u) << "rows 0: one band";
  EXPECT_THROW(flowBandsOf(0), std::invalid_argument);
  EXPECT_THROW(flowBandsOf(100, {-1, 0}), std::invalid_argument);
  EXPECT_THROW(flowBandsOf(100, {1, 0}), std::invalid_argument) << "bands of one row would be empty";
}

TEST(IrradianceFlow, RowsComputedAloneAreTheWholeFramesBitsAndReadOnlyTheirBands) {
  auto [k0, k1] = translatedPair();
  const IrradianceFlows whole = irradianceFlowRows(k0.rows(), k1.rows(), 0, kBandedHeight, FlowSettings{}, kBanding);
  EXPECT_EQ(whole.bands, 4);
  auto [a0, a1] = translatedPair();
  const int first = 70, end = 120;  // within bands 1 ([50, 100)) and 2 ([100, 150))
  const IrradianceFlows alone = irradianceFlowRows(a0.rows(), a1.rows(), first, end, FlowSettings{}, kBanding);
  EXPECT_EQ(alone.bands, 2);
  const size_t offset = static_cast<size_t>(first * kBandedWidth), count = static_cast<size_t>((end - first) * kBandedWidth);
  const auto rowsOf = [&](const std::vector<float>& plane) {
    return std::vector<float>(plane.begin() + static_cast<ptrdiff_t>(offset),
                              plane.begin() + static_cast<ptrdiff_t>(offset + count));
  };
  for (const auto& [field, rows] : {std::pair{&whole.forward, &alone.forward}, std::pair{&whole.backward, &alone.backward}}) {
    EXPECT_EQ(rows->top, first);
    EXPECT_EQ(rows->frameHeight, kBandedHeight);
    EXPECT_TRUE(rowsOf(field->x) == rows->x);
    EXPECT_TRUE(rowsOf(field->y) == rows->y);
    EXPECT_TRUE(rowsOf(field->valid) == rows->valid);
  }
  // Each keyframe's rows: the two bands' halos, [34, 116) and [84, 166), and beyond them
  // the irradiance of the rows the other keyframe's motion (7 rows) leads to, and the row
  // below: above the halo in keyframe 0, below it in keyframe 1.
  for (const SyntheticKeyframe* keyframe : {&a0, &a1})
    EXPECT_EQ(keyframe->rowsRead, (std::vector<std::pair<int, int>>{{34, 116}, {84, 166}}));
  EXPECT_EQ(a0.irradianceRead, (std::vector<std::pair<int, int>>{{27, 34}, {77, 84}}));
  EXPECT_EQ(a1.irradianceRead, (std::vector<std::pair<int, int>>{{116, 124}, {166, 174}}));
}

// The worst distance from the true translation, away from the frame's edges (where the
// data term holds), rows next to the band borders (50, 100, 150) included.
// With `trusted`, the flows are valid there too: their two directions agree.
double worstFlowError(FlowBanding banding, bool trusted) {
  auto [k0, k1] = translatedPair();
  const IrradianceFlows flows = irradianceFlowRows(k0.rows(), k1.rows(), 0, kBandedHeight, FlowSettings{}, banding);
  double worst = 0.0;
  for (int y = 12; y < kBandedHeight - 12; ++y)
    for (int x = 6; x < kBandedWidth - 6; ++x) {
      const size_t p = static_cast<size_t>(y * kBandedWidth + x);
      if (trusted && (flows.forward.valid[p] != 1.0f || flows.backward.valid[p] != 1.0f)) {
        ADD_FAILURE() << "not trusted at " << x << ", " << y;
        return 1e9;
      }
      const double forward = std::hypot(flows.forward.x[p] - kBandedShiftX, flows.forward.y[p] - kBandedShiftY);
      const double backward = std::hypot(flows.backward.x[p] + kBandedShiftX, flows.backward.y[p] + kBandedShiftY);
      worst = std::max({worst, forward, backward});
    }
  return worst;
}

// A motion longer than a band's halo leads wholly outside it: the band reads those rows
// alone, and rows computed alone are still the whole frame's bits.
TEST(IrradianceFlow, AMotionBeyondTheHaloReadsTheRowsItLeadsTo) {
  const auto farPair = [] {
    return std::pair{SyntheticKeyframe{0.0f, 0.0f, 0.0f, 90.0f}, SyntheticKeyframe{0.0f, 90.0f, 0.0f, -90.0f}};
  };
  auto [k0, k1] = farPair();
  const IrradianceFlows whole = irradianceFlowRows(k0.rows(), k1.rows(), 0, kBandedHeight, FlowSettings{}, kBanding);
  auto [a0, a1] = farPair();
  const IrradianceFlows alone = irradianceFlowRows(a0.rows(), a1.rows(), 50, 100, FlowSettings{}, kBanding);
  const auto rows = [](const std::vector<float>& plane) {
    return std::vector<float>(plane.begin() + 50 * kBandedWidth, plane.begin() + 100 * kBandedWidth);
  };
  EXPECT_TRUE(rows(whole.forward.x) == alone.forward.x && rows(whole.forward.y) == alone.forward.y);
  EXPECT_TRUE(rows(whole.backward.x) == alone.backward.x && rows(whole.backward.y) == alone.backward.y);
  // Band 1's halo is [34, 116): its sources lie 90 rows away, within the frame.
  EXPECT_EQ(a1.irradianceRead, (std::vector<std::pair<int, int>>{{124, 200}}));
  EXPECT_EQ(a0.irradianceRead, (std::vector<std::pair<int, int>>{{0, 27}}));
}

TEST(IrradianceFlow, AKnownTranslationIsFoundAcrossBandBorders) {
  EXPECT_LT(worstFlowError(FlowBanding{0, 0}, true), 0.05) << "one solve";
  EXPECT_LT(worstFlowError(kBanding, false), 0.05) << "bands with their halo";
  EXPECT_GT(worstFlowError(FlowBanding{kBanding.rows, 0}, false), 0.05) << "bands without a halo err at their borders";
  // The check looks a pixel's flow up in the other direction's over the band's halo, a
  // motion's length (7 rows) beyond the band, where a halo of 16 rows is not enough to
  // agree within half a pixel; 24 rows are.
  EXPECT_LT(worstFlowError(FlowBanding{kBanding.rows, 24}, true), 0.05) << "bands with a wider halo";
}

// Bilinear, clamped to the frame (as the forward-backward check looks the other flow up).
float lookup(const std::vector<float>& plane, float x, float y) {
  x = std::clamp(x, 0.0f, static_cast<float>(kBandedWidth - 1));
  y = std::clamp(y, 0.0f, static_cast<float>(kBandedHeight - 1));
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const int x1 = std::min(x0 + 1, kBandedWidth - 1), y1 = std::min(y0 + 1, kBandedHeight - 1);
  const float fx = x - static_cast<float>(x0), fy = y - static_cast<float>(y0);
  const auto at = [&](int px, int py) { return plane[static_cast<size_t>(py * kBandedWidth + px)]; };
  return (at(x0, y0) * (1 - fx) + at(x1, y0) * fx) * (1 - fy) + (at(x0, y1) * (1 - fx) + at(x1, y1) * fx) * fy;
}

// Where the two directions disagree, the flows are invalid (the interpolation then takes the
// primary motion). Made to disagree here: keyframe 1's primary motion points the wrong way
// (7 rows down, as keyframe 0's), and a pyramid of one level cannot find the true backward
// motion 14 rows from that guess. The check changes validity only, and agrees with the
// round trip computed here.
TEST(IrradianceFlow, FlowsWhoseTwoDirectionsDisagreeAreInvalid) {
  auto [k0, k1] = translatedPair();
  k1.motionX = 2.0f;
  k1.motionY = 7.0f;
  FlowSettings oneLevel;
  oneLevel.maxLevels = 1;
  const FlowBanding oneSolve{0, 0};
  const IrradianceFlows checked = irradianceFlowRows(k0.rows(), k1.rows(), 0, kBandedHeight, oneLevel, oneSolve);
  const IrradianceFlows unchecked = irradianceFlowRows(k0.rows(), k1.rows(), 0, kBandedHeight, oneLevel, oneSolve, 0.0f);
  size_t invalid = 0, uncheckedInvalid = 0, decided = 0;
  for (const bool forward : {true, false}) {
    const MotionField& flow = forward ? checked.forward : checked.backward;
    const MotionField& back = forward ? checked.backward : checked.forward;
    const MotionField& plain = forward ? unchecked.forward : unchecked.backward;
    EXPECT_TRUE(flow.x == plain.x && flow.y == plain.y);
    for (int y = 0; y < kBandedHeight; ++y)
      for (int x = 0; x < kBandedWidth; ++x) {
        const size_t p = static_cast<size_t>(y * kBandedWidth + x);
        const float tx = static_cast<float>(x) + flow.x[p], ty = static_cast<float>(y) + flow.y[p];
        const double roundTrip = std::hypot(flow.x[p] + lookup(back.x, tx, ty), flow.y[p] + lookup(back.y, tx, ty));
        invalid += flow.valid[p] == 0.0f ? 1 : 0;
        uncheckedInvalid += plain.valid[p] == 0.0f ? 1 : 0;
        if (plain.valid[p] == 0.0f) {
          ASSERT_EQ(flow.valid[p], 0.0f);
        } else if (std::fabs(roundTrip - kFlowConsistency) > 1e-3) {  // clear of rounding at the bound
          ASSERT_EQ(flow.valid[p], roundTrip <= kFlowConsistency ? 1.0f : 0.0f) << x << ", " << y << ": " << roundTrip;
          ++decided;
        }
      }
  }
  const size_t pixels = 2 * static_cast<size_t>(kBandedWidth * kBandedHeight);
  EXPECT_GT(decided, pixels * 9 / 10);
  EXPECT_GT(invalid, uncheckedInvalid + pixels / 4) << "the check leaves the contradicted flows invalid";
  EXPECT_THROW(irradianceFlowRows(k0.rows(), k1.rows(), 0, kBandedHeight, oneLevel, oneSolve, -1.0f),
               std::invalid_argument);
}

TEST(IrradianceFlow, ABandWithoutTheComponentInEitherKeyframeIsLeftInvalid) {
  auto [k0, k1] = translatedPair();
  k0.emptyEnd = k1.emptyEnd = 66;  // band 0's halo, [0, 66)
  const IrradianceFlows flows =
      irradianceFlowRows(k0.rows(), k1.rows(), 0, kBandedHeight, FlowSettings{}, kBanding, 0.0f);
  EXPECT_EQ(flows.bands, 4);
  EXPECT_EQ(flows.bandsSkipped, 1);
  // Band 0's rows are invalid; the others valid where the flow lands inside the frame (not
  // checked against each other here).
  for (const MotionField* flow : {&flows.forward, &flows.backward})
    for (int y = 0; y < kBandedHeight; ++y)
      for (int x = 0; x < kBandedWidth; ++x) {
        const size_t p = static_cast<size_t>(y * kBandedWidth + x);
        const float tx = static_cast<float>(x) + flow->x[p], ty = static_cast<float>(y) + flow->y[p];
        const bool lands = tx > -0.5f && tx < kBandedWidth - 0.5f && ty > -0.5f && ty < kBandedHeight - 0.5f;
        ASSERT_EQ(flow->valid[p], y >= 50 && lands ? 1.0f : 0.0f) << x << ", " << y;
      }
}

TEST(IrradianceFlow, RowsOutsideTheFrameAreRefused) {
  auto [k0, k1] = translatedPair();
  EXPECT_THROW(irradianceFlowRows(k0.rows(), k1.rows(), 150, kBandedHeight + 1, FlowSettings{}, kBanding),
               std::invalid_argument);
  EXPECT_THROW(irradianceFlowRows(k0.rows(), k1.rows(), 20, 20, FlowSettings{}, kBanding), std::invalid_argument);
}

}  // namespace
}  // namespace pathfarm
