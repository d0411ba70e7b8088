#include "postproc/interpolation/solid_regions.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>

namespace pathfarm {
namespace {

constexpr int kWidth = 40, kHeight = 30;

size_t at(int x, int y) { return static_cast<size_t>(y) * kWidth + static_cast<size_t>(x); }

// The opening computed the long way, pixel by pixel: a pixel stays when some square of
// side 2 r + 1 holding it has every pixel inside the frame flagged.
std::vector<uint8_t> openedByHand(const std::vector<uint8_t>& mask, int r) {
  const auto solidAt = [&](int cx, int cy) {
    for (int y = cy - r; y <= cy + r; ++y)
      for (int x = cx - r; x <= cx + r; ++x)
        if (x >= 0 && y >= 0 && x < kWidth && y < kHeight && !mask[at(x, y)]) return false;
    return true;
  };
  std::vector<uint8_t> kept(mask.size(), 0);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x)
      for (int cy = y - r; cy <= y + r && !kept[at(x, y)]; ++cy)
        for (int cx = x - r; cx <= x + r; ++cx)
          if (cx >= 0 && cy >= 0 && cx < kWidth && cy < kHeight && solidAt(cx, cy)) {
            kept[at(x, y)] = 1;
            break;
          }
  return kept;
}

std::vector<uint8_t> withRectangles(const std::vector<std::array<int, 4>>& rectangles) {
  std::vector<uint8_t> mask(static_cast<size_t>(kWidth * kHeight), 0);
  for (const auto& [x0, y0, x1, y1] : rectangles)
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) mask[at(x, y)] = 1;
  return mask;
}

TEST(SolidRegions, SpecksAndThinLinesVanishAndASquareStays) {
  // A lone pixel, a 2 x 2 block, a line 2 pixels wide; and a 3 x 3 square.
  const auto mask = withRectangles({{5, 5, 6, 6}, {10, 5, 12, 7}, {15, 3, 17, 20}, {25, 10, 28, 13}});
  const auto kept = solidRegions(mask, kWidth, kHeight, 1);
  EXPECT_EQ(kept, withRectangles({{25, 10, 28, 13}}));
  EXPECT_EQ(solidRegions(mask, kWidth, kHeight, 0), mask);
}

TEST(SolidRegions, ARegionAlongTheFrameEdgeIsKept) {
  // Two pixels wide, against the left edge and the bottom: the frame's outside counts as flagged.
  const auto mask = withRectangles({{0, 0, 2, kHeight}, {10, kHeight - 2, 30, kHeight}});
  EXPECT_EQ(solidRegions(mask, kWidth, kHeight, 1), mask);
}

TEST(SolidRegions, AgreesWithTheOpeningComputedPixelByPixel) {
  std::mt19937 random(11);
  for (const double density : {0.3, 0.6, 0.85}) {
    std::bernoulli_distribution flag(density);
    std::vector<uint8_t> mask(static_cast<size_t>(kWidth * kHeight));
    for (uint8_t& m : mask) m = flag(random) ? 1 : 0;
    for (const int r : {1, 2}) EXPECT_EQ(solidRegions(mask, kWidth, kHeight, r), openedByHand(mask, r)) << density << " " << r;
  }
}

TEST(SolidRegions, WhatAWindowCheckFlagsAroundARealDifferenceIsLeftExactlyAsItWas) {
  // Every pixel within 3 of a few scattered sources (7 x 7 windows that hold one): a set
  // made of 7 x 7 squares, which an opening by 3 x 3 squares cannot change.
  std::mt19937 random(5);
  std::uniform_int_distribution<int> x(0, kWidth - 1), y(0, kHeight - 1);
  std::vector<std::array<int, 4>> windows;
  for (int i = 0; i < 6; ++i) {
    const int sx = x(random), sy = y(random);
    windows.push_back({std::max(0, sx - 3), std::max(0, sy - 3), std::min(kWidth, sx + 4), std::min(kHeight, sy + 4)});
  }
  const auto mask = withRectangles(windows);
  EXPECT_EQ(solidRegions(mask, kWidth, kHeight, 1), mask);
}

}  // namespace
}  // namespace pathfarm
