// Backward warping along the current frame's motion: integer shifts are exact, sources
// outside the image or invalid motion give valid 0.
#include "postproc/filters/warp.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace pathfarm {
namespace {

// A test pattern with a distinct value per pixel and channel.
Planes pattern(int w, int h) {
  Planes planes(w, h, 2);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      planes.channels[0][static_cast<size_t>(y * w + x)] = static_cast<float>(x) + 100.0f * static_cast<float>(y);
      planes.channels[1][static_cast<size_t>(y * w + x)] = std::sin(static_cast<float>(x * 7 + y * 13));
    }
  return planes;
}

MotionField uniformMotion(int w, int h, float mx, float my) {
  MotionField motion;
  motion.width = w;
  motion.height = h;
  motion.x.assign(static_cast<size_t>(w * h), mx);
  motion.y.assign(static_cast<size_t>(w * h), my);
  return motion;
}

TEST(Warp, IntegerMotionWarpsAShiftedFrameBackExactly) {
  const int w = 23, h = 17, sx = 3, sy = -2;
  const Planes current = pattern(w, h);
  // The neighbour frame sees everything moved by (sx, sy): neighbour(p + s) = current(p).
  Planes neighbour(w, h, 2);
  for (size_t c = 0; c < 2; ++c)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const int fromX = x - sx, fromY = y - sy;
        neighbour.channels[c][static_cast<size_t>(y * w + x)] =
            fromX >= 0 && fromX < w && fromY >= 0 && fromY < h
                ? current.channels[c][static_cast<size_t>(fromY * w + fromX)]
                : -1.0f;
      }
  const MotionField motion = uniformMotion(w, h, sx, sy);
  const std::vector<float> valid = warpValidity(motion);
  for (WarpLookup lookup : {WarpLookup::Bilinear, WarpLookup::Nearest}) {
    const Planes warped = warpPlanes(neighbour, motion, lookup);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const size_t p = static_cast<size_t>(y * w + x);
        const bool inside = x + sx < w && y + sy >= 0;
        ASSERT_EQ(valid[p], inside ? 1.0f : 0.0f) << x << "," << y;
        if (!inside) continue;
        for (size_t c = 0; c < 2; ++c) ASSERT_EQ(warped.channels[c][p], current.channels[c][p]) << x << "," << y;
      }
    }
  }
}

TEST(Warp, BilinearBetweenPixelCentresAndNearestForIds) {
  const Planes source = pattern(8, 6);
  const MotionField motion = uniformMotion(8, 6, 0.5f, 0.25f);
  const Planes bilinear = warpPlanes(source, motion);
  // Pixel (2, 1) looks up (2.5, 1.25): x 2.5 + 100 * 1.25 = 127.5 (the pattern is linear).
  EXPECT_FLOAT_EQ(bilinear.channels[0][1 * 8 + 2], 127.5f);
  const Planes nearest = warpPlanes(source, motion, WarpLookup::Nearest);
  const float v = nearest.channels[0][1 * 8 + 2];
  EXPECT_TRUE(v == 102.0f || v == 103.0f) << v;  // never a blend
  // The last column looks up x = 7.5: outside the footprints.
  EXPECT_EQ(warpValidity(motion)[1 * 8 + 7], 0.0f);
  EXPECT_EQ(warpValidity(motion)[5 * 8 + 2], 1.0f);  // y = 5.25 is still inside pixel 5
}

TEST(Warp, InvalidMotionGivesValidZero) {
  MotionField motion = uniformMotion(5, 4, 1.0f, 0.0f);
  motion.valid.assign(20, 1.0f);
  motion.valid[6] = 0.0f;
  motion.x[7] = std::numeric_limits<float>::quiet_NaN();
  motion.y[8] = std::numeric_limits<float>::infinity();
  const std::vector<float> valid = warpValidity(motion);
  EXPECT_EQ(valid[5], 1.0f);
  EXPECT_EQ(valid[6], 0.0f);
  EXPECT_EQ(valid[7], 0.0f);
  EXPECT_EQ(valid[8], 0.0f);
  EXPECT_EQ(valid[9], 0.0f);  // the last column: its source is outside
  const Planes warped = warpPlanes(pattern(5, 4), motion);
  for (const auto& plane : warped.channels)
    for (float v : plane) EXPECT_TRUE(std::isfinite(v));
  // Far outside: clamped, plausible values, invalid.
  const MotionField far = uniformMotion(5, 4, 1e9f, -1e9f);
  EXPECT_EQ(warpValidity(far), std::vector<float>(20, 0.0f));
  const Planes clamped = warpPlanes(pattern(5, 4), far);
  for (float v : clamped.channels[0]) EXPECT_TRUE(std::isfinite(v));
}

TEST(Warp, ReadsTheFramesMotionChannels) {
  FrameImage frame(4, 3);
  frame.addChannel("motion.X").assign(12, 1.0f);
  frame.addChannel("motion.Y").assign(12, 0.0f);
  frame.addChannel("reflection.motion_back.X").assign(12, -2.0f);
  frame.addChannel("reflection.motion_back.Y").assign(12, 0.0f);
  frame.addChannel("reflection.motion_valid.Y").assign(12, 0.0f);
  const MotionField next = motionTowards(frame, NeighbourFrame::Next, "", "frame.exr");
  EXPECT_EQ(next.x, std::vector<float>(12, 1.0f));
  EXPECT_TRUE(next.valid.empty());
  const MotionField back = motionTowards(frame, NeighbourFrame::Previous, "reflection.", "frame.exr");
  EXPECT_EQ(back.x, std::vector<float>(12, -2.0f));
  EXPECT_EQ(warpValidity(back), std::vector<float>(12, 0.0f));
  try {
    motionTowards(frame, NeighbourFrame::Previous, "", "frame.exr");
    FAIL() << "no motion_back in the frame";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "frame.exr: missing channel \"motion_back.X\"");
  }
  EXPECT_THROW(warpPlanes(pattern(4, 4), next), std::invalid_argument);  // 4x4 planes, 4x3 motion
}

}  // namespace
}  // namespace pathfarm
