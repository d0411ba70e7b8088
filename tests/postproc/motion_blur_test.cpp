// Post-process motion blur: a translating constant square blurs into the analytic box
// blur, undefined motion is inpainted, and bad input is refused with the layer named.
#include "postproc/motion_blur/motion_blur.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>

namespace pathfarm {
namespace {

// One component ("residual") on a static background at depth 10: a square of value 1 at
// depth 1 moving `speed` pixels per frame in x.
FrameImage squareFrame(int w, int h, int x0, int x1, int y0, int y1, float speed) {
  FrameImage f(w, h);
  f.attributes()["pathfarm.decomposition"] = "residual";
  for (const char* c : {"R", "G", "B", "residual.color.R", "residual.color.G", "residual.color.B", "residual.depth.Z",
                        "residual.motion.X", "residual.motion.Y", "residual.motion_back.X", "residual.motion_back.Y",
                        "residual.motion_valid.Y"})
    f.addChannel(c);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t p = static_cast<size_t>(y * w + x);
      const bool in = x >= x0 && x < x1 && y >= y0 && y < y1;
      for (const char* c : {"R", "G", "B", "residual.color.R", "residual.color.G", "residual.color.B"})
        f.channel(c)[p] = in ? 1.0f : 0.0f;
      f.channel("residual.depth.Z")[p] = in ? 1.0f : 10.0f;
      f.channel("residual.motion.X")[p] = in ? speed : 0.0f;
      f.channel("residual.motion_back.X")[p] = in ? -speed : 0.0f;
      f.channel("residual.motion_valid.Y")[p] = 1.0f;
    }
  return f;
}

TEST(MotionBlur, TranslatingSquareMatchesTheAnalyticBoxBlur) {
  const int w = 64, h = 24, x0 = 20, x1 = 36, y0 = 4, y1 = 20;
  const float speed = 8.0f;
  const FrameImage frame = squareFrame(w, h, x0, x1, y0, y1, speed);
  MotionBlurSettings settings;
  settings.steps = 64;
  const FrameImage blurred = motionBlur(frame, 1.0f, settings);
  double maxError = 0, sumError = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      // Centered shutter: the square's footprint [x0 - 0.5, x1 - 0.5) swept over [-4, 4].
      double expected = 0;
      if (y >= y0 && y < y1) {
        const double lo = std::max(static_cast<double>(x) - speed / 2, x0 - 0.5);
        const double hi = std::min(static_cast<double>(x) + speed / 2, x1 - 0.5);
        expected = std::max(0.0, hi - lo) / speed;
      }
      const size_t p = static_cast<size_t>(y * w + x);
      const double error = std::fabs(blurred.channel("R")[p] - expected);
      maxError = std::max(maxError, error);
      sumError += error;
      ASSERT_FLOAT_EQ(blurred.channel("R")[p], blurred.channel("residual.color.R")[p]);
    }
  const double meanError = sumError / (w * h);
  std::printf("motion blur: max error %.4f, mean error %.5f\n", maxError, meanError);
  EXPECT_LT(maxError, 0.08);
  EXPECT_LT(meanError, 0.005);
  // Energy is kept: the square's total is unchanged.
  double before = 0, after = 0;
  for (size_t p = 0; p < frame.pixelCount(); ++p) {
    before += frame.channel("R")[p];
    after += blurred.channel("R")[p];
  }
  EXPECT_NEAR(after, before, 0.01 * before);
  EXPECT_EQ(blurred.attributes().at("pathfarm.motion_blur"), std::to_string(1.0f));
}

TEST(MotionBlur, UndefinedMotionIsInpaintedAndZeroExposureIsIdentity) {
  FrameImage frame = squareFrame(32, 16, 8, 16, 4, 12, 6.0f);
  const FrameImage expected = motionBlur(frame, 1.0f);
  // The component's motion is undefined everywhere; the frame-wide primary motion (here the
  // same as the component's) stands in, so the blur is unchanged.
  for (const char* c : {"motion.X", "motion.Y", "motion_back.X", "motion_back.Y"})
    frame.addChannel(c) = frame.channel(std::string("residual.") + c);
  for (float& v : frame.channel("residual.motion_valid.Y")) v = 0.0f;
  EXPECT_EQ(motionBlur(frame, 1.0f).channel("R"), expected.channel("R"));
  // Undefined inside the square only: its motion comes from its nearest valid pixels,
  // which are the (static) background, so it stays sharp.
  FrameImage partly = squareFrame(32, 16, 8, 16, 4, 12, 6.0f);
  for (int y = 4; y < 12; ++y)
    for (int x = 8; x < 16; ++x) partly.channel("residual.motion_valid.Y")[static_cast<size_t>(y * 32 + x)] = 0.0f;
  EXPECT_EQ(motionBlur(partly, 1.0f).channel("R"), partly.channel("R"));
  frame.channel("residual.motion_valid.Y").assign(frame.pixelCount(), 1.0f);
  EXPECT_EQ(motionBlur(frame, 0.0f).channel("R"), frame.channel("R"));
  // Opening shutter: the square only smears forward (right).
  MotionBlurSettings opening;
  opening.shutter = Shutter::Opening;
  const FrameImage forward = motionBlur(frame, 1.0f, opening);
  EXPECT_EQ(forward.channel("R")[static_cast<size_t>(8 * 32 + 6)], 0.0f);
  EXPECT_GT(forward.channel("R")[static_cast<size_t>(8 * 32 + 18)], 0.2f);
}

TEST(MotionBlur, BadInputIsRefusedWithTheLayerNamed) {
  const FrameImage good = squareFrame(16, 8, 4, 8, 2, 6, 2.0f);
  auto expectMessage = [](const FrameImage& f, float exposure, const std::string& needle) {
    try {
      motionBlur(f, exposure);
      ADD_FAILURE() << "no exception, expected " << needle;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  FrameImage missing(16, 8);
  missing.attributes() = good.attributes();
  for (const std::string& name : good.channelNames())
    if (name != "residual.motion_back.X") missing.addChannel(name) = good.channel(name);
  expectMessage(missing, 1.0f, "residual.motion_back.X");
  FrameImage broken = good;
  broken.channel("residual.motion.X")[3] = std::numeric_limits<float>::quiet_NaN();
  expectMessage(broken, 1.0f, "residual.motion.X");
  expectMessage(good, -1.0f, "exposure");
  expectMessage(good, std::numeric_limits<float>::infinity(), "exposure");
}

TEST(MotionBlur, StaticFrameIsExactAndEnergyIsConserved) {
  // Zero motion: every source lands on its own pixel centre with weight exactly 1, so each
  // step returns the frame and so does their mean.
  const FrameImage still = squareFrame(32, 16, 8, 16, 4, 12, 0.0f);
  const FrameImage stillBlurred = motionBlur(still, 1.0f);
  EXPECT_EQ(stillBlurred.channel("R"), still.channel("R"));
  EXPECT_EQ(stillBlurred.channel("residual.color.R"), still.channel("residual.color.R"));
  // A square over a zero background, moving by a fractional diagonal step and staying
  // inside the image: each source's bilinear weights sum to 1, the square's contributions
  // all pass the depth test and the background adds (1 - w) * 0, so every step keeps the
  // square's total up to float rounding of the weights (relative 1e-5 is ~100 ulps).
  for (const Shutter shutter : {Shutter::Centered, Shutter::Opening}) {
    FrameImage frame = squareFrame(64, 48, 20, 33, 15, 29, 5.3f);
    for (size_t p = 0; p < frame.pixelCount(); ++p) {
      const bool in = frame.channel("residual.depth.Z")[p] == 1.0f;
      frame.channel("residual.motion.Y")[p] = in ? -2.7f : 0.0f;
      frame.channel("residual.motion_back.Y")[p] = in ? 2.7f : 0.0f;
    }
    MotionBlurSettings settings;
    settings.steps = 13;
    settings.shutter = shutter;
    const FrameImage blurred = motionBlur(frame, 1.0f, settings);
    double before = 0, after = 0;
    for (size_t p = 0; p < frame.pixelCount(); ++p) {
      before += frame.channel("R")[p];
      after += blurred.channel("R")[p];
      EXPECT_GE(blurred.channel("R")[p], 0.0f);
      EXPECT_LE(blurred.channel("R")[p], 1.0f + 1e-6f);
    }
    EXPECT_NEAR(after, before, 1e-5 * before) << (shutter == Shutter::Centered ? "centered" : "opening");
  }
}

}  // namespace
}  // namespace pathfarm
