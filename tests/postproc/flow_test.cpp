// Variational optical flow: sub-pixel translation and rotation of a smooth texture, a
// pyramid cut to one level missing a larger translation, bootstrapping a moving soft
// shadow over a static floor in the log domain, forward-backward occlusions of a moving
// square, determinism across thread counts, and bad input.
#include "postproc/flow/optical_flow.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <utility>
#include <limits>
#include <random>
#include <stdexcept>

namespace pathfarm {
namespace {

// A smooth random texture: per channel a sum of sinusoids of wavelengths 6..24 px,
// continuous so it can be sampled at any position.
struct Texture {
  struct Wave {
    float kx, ky, phase, amplitude;
  };
  std::vector<std::vector<Wave>> channels;

  Texture(int channelCount, unsigned seed, float contrast = 1.0f) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    for (int c = 0; c < channelCount; ++c) {
      std::vector<Wave> waves;
      for (int i = 0; i < 8; ++i) {
        const float wavelength = 6.0f + 18.0f * unit(rng);
        const float angle = 6.2831853f * unit(rng);
        const float k = 6.2831853f / wavelength;
        waves.push_back({k * std::cos(angle), k * std::sin(angle), 6.2831853f * unit(rng),
                         contrast * (0.04f + 0.06f * unit(rng))});
      }
      channels.push_back(waves);
    }
  }
  float operator()(int c, float x, float y) const {
    float value = 0.5f;
    for (const Wave& wave : channels[static_cast<size_t>(c)])
      value += wave.amplitude * std::sin(wave.kx * x + wave.ky * y + wave.phase);
    return value;
  }
};

// image(x, y) = f(c, x, y) for every pixel.
Planes render(int w, int h, int channels, const std::function<float(int, float, float)>& f) {
  Planes planes(w, h, channels);
  for (int c = 0; c < channels; ++c)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        planes.channels[static_cast<size_t>(c)][static_cast<size_t>(y * w + x)] =
            f(c, static_cast<float>(x), static_cast<float>(y));
  return planes;
}

// Average endpoint error against flow(x, y) over pixels at least `margin` from the border.
double averageEpe(const FlowField& flow, int margin, const std::function<std::pair<float, float>(float, float)>& truth) {
  double sum = 0;
  size_t count = 0;
  for (int y = margin; y < flow.height - margin; ++y)
    for (int x = margin; x < flow.width - margin; ++x) {
      const size_t p = static_cast<size_t>(y * flow.width + x);
      const auto [tx, ty] = truth(static_cast<float>(x), static_cast<float>(y));
      sum += std::hypot(flow.dx[p] - tx, flow.dy[p] - ty);
      ++count;
    }
  return sum / static_cast<double>(count);
}

// An 80x80 RGB texture A and B, the texture moved by (mx, my): A(p) = B(p + m).
std::pair<Planes, Planes> translatedTexture(float mx, float my) {
  const Texture texture(3, 7);
  return {render(80, 80, 3, [&](int c, float x, float y) { return texture(c, x, y); }),
          render(80, 80, 3, [&](int c, float x, float y) { return texture(c, x - mx, y - my); })};
}

TEST(OpticalFlow, SubPixelTranslationOfAnRgbTexture) {
  const float mx = 2.3f, my = -1.7f;
  const auto [a, b] = translatedTexture(mx, my);
  const FlowSettings settings;
  const FlowField flow = computeFlow(a, b, settings);
  const double epe = averageEpe(flow, 8, [&](float, float) { return std::pair{mx, my}; });
  std::printf("translation EPE %.4f px\n", epe);
  EXPECT_LT(epe, 0.1);

  FlowSettings withGradient = settings;
  withGradient.gradientWeight = 1.0f;
  const double epeGradient =
      averageEpe(computeFlow(a, b, withGradient), 8, [&](float, float) { return std::pair{mx, my}; });
  std::printf("translation EPE with gradient constancy %.4f px\n", epeGradient);
  EXPECT_LT(epeGradient, 0.1);
}

// The pyramid is what finds motions longer than the texture's detail: cut to one level, the
// solver settles in a local minimum near its start.
TEST(OpticalFlow, APyramidCutToOneLevelMissesALargeMotion) {
  const float mx = 4.5f, my = -3.0f;
  const auto [a, b] = translatedTexture(mx, my);
  const auto epe = [&](int maxLevels) {
    FlowSettings settings;
    settings.maxLevels = maxLevels;
    return averageEpe(computeFlow(a, b, settings), 12, [&](float, float) { return std::pair{mx, my}; });
  };
  EXPECT_LT(epe(0), 0.1) << "the whole pyramid";
  EXPECT_GT(epe(1), 1.0) << "one level";
}

TEST(OpticalFlow, SmallRotationAboutTheCentre) {
  const int w = 96, h = 96;
  const float cx = 47.5f, cy = 47.5f, angle = 3.0f * 3.14159265f / 180.0f;
  const float cs = std::cos(angle), sn = std::sin(angle);
  const Texture texture(3, 11);
  // B(R (p - c) + c) = A(p): B samples the texture at R^-1 (q - c) + c.
  const Planes a = render(w, h, 3, [&](int c, float x, float y) { return texture(c, x, y); });
  const Planes b = render(w, h, 3, [&](int c, float x, float y) {
    const float rx = x - cx, ry = y - cy;
    return texture(c, cs * rx + sn * ry + cx, -sn * rx + cs * ry + cy);
  });
  const FlowField flow = computeFlow(a, b, FlowSettings{});
  const double epe = averageEpe(flow, 8, [&](float x, float y) {
    const float rx = x - cx, ry = y - cy;
    return std::pair{cs * rx - sn * ry + cx - x, sn * rx + cs * ry + cy - y};
  });
  std::printf("rotation EPE %.4f px\n", epe);
  EXPECT_LT(epe, 0.15);
}

// A static textured floor under a soft shadow that moves by s between A and B; the geometry
// (primary motion) is static. In the log domain the shadow is an additive blob, but the floor's
// texture (static, log-amplitude up to ~0.1) pulls the flow towards zero wherever the blob's
// gradient is weak, and on the shadow's edge only the component normal to the edge is
// observable (aperture problem): the tangential one comes from the smoothness term along the
// curved edge and is pulled towards the static floor on both sides of the edge. Documented
// tolerances on the edge region (|grad log shadow| >= 0.1 per px), measured 0.21 px and 1.20 px:
//   - normal component: mean error < 0.35 px and < 1/5 of the primary motion's (~2.3 px);
//   - full endpoint error: < 0.45 of the primary motion's (3.6 px).
TEST(OpticalFlow, BootstrappingRecoversAMovingShadowInTheLogDomain) {
  const int w = 96, h = 96;
  const float sx = 3.0f, sy = 2.0f;     // the shadow's motion from A to B
  const Texture texture(3, 23, 0.25f);  // a low-contrast static floor
  // A soft dark blob: irradiance falls to 0.2 inside a disc of radius 10 with ~10 px soft edges.
  auto shadow = [](float x, float y) {
    const float r = std::hypot(x - 45.0f, y - 46.0f);
    const float t = 1.0f / (1.0f + std::exp(-(r - 10.0f) / 2.5f));
    return 0.2f + 0.8f * t;
  };
  const Planes a = render(w, h, 3, [&](int c, float x, float y) { return texture(c, x, y) * shadow(x, y); });
  const Planes b =
      render(w, h, 3, [&](int c, float x, float y) { return texture(c, x, y) * shadow(x - sx, y - sy); });
  const FlowField primary(w, h);  // the geometry does not move

  FlowSettings settings;
  settings.logDomain = true;
  const FlowField flow = bootstrappedFlow(a, b, primary, settings);

  double errFlow = 0, errZero = 0, errNormal = 0, errNormalZero = 0;
  size_t count = 0;
  for (int y = 4; y < h - 4; ++y)
    for (int x = 4; x < w - 4; ++x) {
      const float fx = static_cast<float>(x), fy = static_cast<float>(y);
      const float gx = std::log(shadow(fx + 0.5f, fy)) - std::log(shadow(fx - 0.5f, fy));
      const float gy = std::log(shadow(fx, fy + 0.5f)) - std::log(shadow(fx, fy - 0.5f));
      const float g = std::hypot(gx, gy);
      if (g < 0.1f) continue;
      const size_t p = static_cast<size_t>(y * w + x);
      const float ex = flow.dx[p] - sx, ey = flow.dy[p] - sy;
      errFlow += std::hypot(ex, ey);
      errZero += std::hypot(sx, sy);
      errNormal += std::abs(ex * gx + ey * gy) / g;
      errNormalZero += std::abs(sx * gx + sy * gy) / g;
      ++count;
    }
  ASSERT_GT(count, 200u);
  const double n = static_cast<double>(count);
  std::printf("shadow edge (%zu px): bootstrapped EPE %.3f px (normal %.3f), primary motion %.3f px (normal %.3f)\n",
              count, errFlow / n, errNormal / n, errZero / n, errNormalZero / n);
  EXPECT_LT(errNormal / n, 0.35);
  EXPECT_LT(errNormal, errNormalZero / 5.0);
  EXPECT_LT(errFlow, 0.45 * errZero);

}

// A band of rows (FlowRows) needs of B only the rows its primary motion reads: with those
// alone, or with B whole, the flow is the same bits, also where the motion leaves the
// frame (there the warped B is A's own value). B without them is refused.
TEST(OpticalFlow, ABandNeedsOfBOnlyTheRowsItsMotionReads) {
  const int w = 40, frameHeight = 90, top = 30, rows = 30;
  const Texture texture(3, 7);
  const Planes wholeB = render(w, frameHeight, 3, [&](int c, float x, float y) { return texture(c, x - 2.0f, y - 5.0f); });
  const Planes a = render(w, rows, 3, [&](int c, float x, float y) { return texture(c, x, y + top); });
  FlowField primary(w, rows, 2.0f, 5.0f);
  // Some pixels' motion leaves the frame: sideways, and past its last row (which B's rows
  // below do not hold).
  for (int y = 0; y < rows; ++y) primary.dx[static_cast<size_t>(y * w + w - 1)] = 9.0f;
  for (int x = 0; x < w; x += 3) primary.dy[static_cast<size_t>(x)] = 80.0f;
  const FlowRows inWhole{top, frameHeight, 0};
  const FlowField fromWhole = bootstrappedFlow(a, wholeB, primary, FlowSettings{}, nullptr, inWhole);
  // The rows the bilinear lookups read: 35 to 64, and the row below.
  const int first = top + 5, end = top + rows + 5 + 1;
  Planes held(w, end - first, 0);
  for (const auto& plane : wholeB.channels)
    held.channels.emplace_back(plane.begin() + first * w, plane.begin() + end * w);
  const FlowField fromRows = bootstrappedFlow(a, held, primary, FlowSettings{}, nullptr, {top, frameHeight, first});
  EXPECT_TRUE(fromWhole.dx == fromRows.dx && fromWhole.dy == fromRows.dy);
  Planes short1 = held;
  short1.height -= 1;
  for (auto& plane : short1.channels) plane.resize(short1.pixelCount());
  EXPECT_THROW(bootstrappedFlow(a, short1, primary, FlowSettings{}, nullptr, {top, frameHeight, first}),
               std::invalid_argument);
  EXPECT_THROW(bootstrappedFlow(a, held, primary, FlowSettings{}, nullptr, {top, frameHeight, frameHeight - 10}),
               std::invalid_argument)
      << "rows past the frame";
  EXPECT_THROW(bootstrappedFlow(a, wholeB, primary, FlowSettings{}, nullptr, {70, frameHeight, 0}),
               std::invalid_argument)
      << "A's rows past the frame";
}

TEST(OpticalFlow, BootstrappingComposesWithThePrimaryMotion) {
  // A moves by a known translation; the primary motion gives most of it, the residual the rest.
  const int w = 80, h = 80;
  const float mx = 3.4f, my = 1.2f;
  const Texture texture(3, 5);
  const Planes a = render(w, h, 3, [&](int c, float x, float y) { return texture(c, x, y); });
  const Planes b = render(w, h, 3, [&](int c, float x, float y) { return texture(c, x - mx, y - my); });
  const FlowField primary(w, h, 3.0f, 1.0f);
  const FlowField flow = bootstrappedFlow(a, b, primary, FlowSettings{});
  const double epe = averageEpe(flow, 8, [&](float, float) { return std::pair{mx, my}; });
  std::printf("bootstrapped translation EPE %.4f px\n", epe);
  EXPECT_LT(epe, 0.1);
}

// A static background with a square of another texture moving by (mx, 0).
struct SquareScene {
  static constexpr int w = 80, h = 80, x0 = 28, y0 = 28, side = 22;
  float mx;
  Texture background{3, 31}, square{3, 37};

  bool inSquare(float x, float y, float shift) const {
    return x >= static_cast<float>(x0) + shift && x < static_cast<float>(x0 + side) + shift &&
           y >= static_cast<float>(y0) && y < static_cast<float>(y0 + side);
  }
  Planes frame(float shift) const {
    return render(w, h, 3, [&](int c, float x, float y) {
      return inSquare(x, y, shift) ? square(c, x - shift, y) + 0.3f : background(c, x, y);
    });
  }
  // The ground-truth flow of the frame at `from` towards the frame at `to`.
  FlowField truth(float from, float to) const {
    FlowField flow(w, h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        if (inSquare(static_cast<float>(x), static_cast<float>(y), from))
          flow.dx[static_cast<size_t>(y * w + x)] = to - from;
    return flow;
  }
};

TEST(OpticalFlow, ForwardBackwardMarksCoveredAndUncoveredPixels) {
  const SquareScene scene{4.0f};
  const FlowField forward = scene.truth(0.0f, scene.mx), backward = scene.truth(scene.mx, 0.0f);
  const OcclusionResult covered = forwardBackward(forward, backward);
  const OcclusionResult uncovered = forwardBackward(backward, forward);
  size_t expectCovered = 0, expectUncovered = 0;
  for (int y = 0; y < scene.h; ++y)
    for (int x = 0; x < scene.w; ++x) {
      const size_t p = static_cast<size_t>(y * scene.w + x);
      const float fx = static_cast<float>(x), fy = static_cast<float>(y);
      // Covered: background in A, under the square in B. Uncovered: the reverse.
      const bool c = !scene.inSquare(fx, fy, 0.0f) && scene.inSquare(fx, fy, scene.mx);
      const bool u = scene.inSquare(fx, fy, 0.0f) && !scene.inSquare(fx, fy, scene.mx);
      ASSERT_EQ(covered.mask[p], c ? 1.0f : 0.0f) << x << "," << y;
      ASSERT_EQ(uncovered.mask[p], u ? 1.0f : 0.0f) << x << "," << y;
      expectCovered += c;
      expectUncovered += u;
    }
  EXPECT_EQ(covered.count, expectCovered);
  EXPECT_EQ(uncovered.count, expectUncovered);
  EXPECT_EQ(covered.count, 4u * SquareScene::side);

  // Leaving the image is an occlusion.
  const OcclusionResult out = forwardBackward(FlowField(8, 8, -2.0f, 0.0f), FlowField(8, 8, 2.0f, 0.0f));
  EXPECT_EQ(out.count, 8u * 2u);
  EXPECT_EQ(out.mask[0], 1.0f);
  EXPECT_EQ(out.mask[2], 0.0f);
}

TEST(OpticalFlow, FlowWithOcclusionsFromTheSolver) {
  const SquareScene scene{4.0f};
  const Planes a = scene.frame(0.0f), b = scene.frame(scene.mx);
  OcclusionResult occlusion;
  const FlowField flow = flowWithOcclusions(a, b, FlowSettings{}, &occlusion);
  ASSERT_EQ(occlusion.mask.size(), a.pixelCount());
  // Every marked pixel lies near the square's border in A or B (or at the image border), and
  // most of the covered strip is marked.
  size_t coveredMarked = 0, coveredTotal = 0, farMarked = 0;
  for (int y = 0; y < scene.h; ++y)
    for (int x = 0; x < scene.w; ++x) {
      const size_t p = static_cast<size_t>(y * scene.w + x);
      const float fx = static_cast<float>(x), fy = static_cast<float>(y);
      const bool covered = !scene.inSquare(fx, fy, 0.0f) && scene.inSquare(fx, fy, scene.mx);
      coveredTotal += covered;
      coveredMarked += covered && occlusion.mask[p] != 0.0f;
      bool nearBorder = false;
      for (int dy = -3; dy <= 3 && !nearBorder; ++dy)
        for (int dx = -3; dx <= 3 && !nearBorder; ++dx)
          for (float shift : {0.0f, scene.mx})
            if (scene.inSquare(fx, fy, shift) != scene.inSquare(fx + static_cast<float>(dx), fy + static_cast<float>(dy), shift))
              nearBorder = true;
      if (!nearBorder && occlusion.mask[p] != 0.0f) ++farMarked;
    }
  std::printf("occlusions: %zu marked, %zu of %zu covered pixels, %zu away from the square's border\n",
              occlusion.count, coveredMarked, coveredTotal, farMarked);
  EXPECT_EQ(farMarked, 0u);
  EXPECT_GT(coveredMarked, coveredTotal * 6 / 10);
  // The background flow stays near zero and the square's near (mx, 0) away from its border.
  const double epe = averageEpe(flow, 6, [&](float x, float y) {
    return std::pair{scene.inSquare(x, y, 0.0f) ? scene.mx : 0.0f, 0.0f};
  });
  std::printf("occlusion-aware flow EPE %.4f px\n", epe);
  EXPECT_LT(epe, 0.3);
}

TEST(OpticalFlow, SameBitsForAnyThreadCount) {
  const int w = 64, h = 64;
  const Texture texture(3, 3);
  const Planes a = render(w, h, 3, [&](int c, float x, float y) { return texture(c, x, y); });
  const Planes b = render(w, h, 3, [&](int c, float x, float y) { return texture(c, x - 1.5f, y + 0.7f); });
  FlowSettings settings;
  settings.gradientWeight = 0.5f;
  FlowField one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = computeFlow(a, b, settings);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 4);
    two = computeFlow(a, b, settings);
  }
  EXPECT_EQ(one.dx, two.dx);
  EXPECT_EQ(one.dy, two.dy);
}

TEST(OpticalFlow, BadInputThrows) {
  const Texture texture(3, 3);
  const Planes a = render(16, 16, 3, [&](int c, float x, float y) { return texture(c, x, y); });
  const FlowSettings settings;
  EXPECT_THROW(computeFlow(a, render(16, 15, 3, [](int, float, float) { return 0.0f; }), settings),
               std::invalid_argument);
  EXPECT_THROW(computeFlow(a, render(16, 16, 1, [](int, float, float) { return 0.0f; }), settings),
               std::invalid_argument);
  EXPECT_THROW(computeFlow(Planes(), Planes(), settings), std::invalid_argument);
  Planes nan = a;
  nan.channels[1][37] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(computeFlow(a, nan, settings), std::invalid_argument);
  Planes inf = a;
  inf.channels[0][3] = std::numeric_limits<float>::infinity();
  EXPECT_THROW(computeFlow(inf, a, settings), std::invalid_argument);
  Planes shortPlane = a;
  shortPlane.channels[2].pop_back();
  EXPECT_THROW(computeFlow(a, shortPlane, settings), std::invalid_argument);
  const std::vector<float> badMask(10, 0.0f);
  EXPECT_THROW(computeFlow(a, a, settings, &badMask), std::invalid_argument);
  FlowSettings badSettings;
  badSettings.downsample = 0.95f;
  EXPECT_THROW(computeFlow(a, a, badSettings), std::invalid_argument);
  badSettings = FlowSettings{};
  badSettings.lambda = -1.0f;
  EXPECT_THROW(computeFlow(a, a, badSettings), std::invalid_argument);
  badSettings = FlowSettings{};
  badSettings.maxLevels = -1;
  EXPECT_THROW(computeFlow(a, a, badSettings), std::invalid_argument);
  EXPECT_THROW(bootstrappedFlow(a, a, FlowField(8, 8), settings), std::invalid_argument);
  FlowField nanFlow(16, 16);
  nanFlow.dx[5] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(bootstrappedFlow(a, a, nanFlow, settings), std::invalid_argument);
  EXPECT_THROW(forwardBackward(FlowField(16, 16), FlowField(8, 16)), std::invalid_argument);
  EXPECT_THROW(forwardBackward(nanFlow, FlowField(16, 16)), std::invalid_argument);
  EXPECT_THROW(forwardBackward(FlowField(16, 16), FlowField(16, 16), -1.0f), std::invalid_argument);
  try {
    computeFlow(a, nan, settings);
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("non-finite"), std::string::npos) << e.what();
  }
}

TEST(OpticalFlow, TinyImagesGiveFiniteFlow) {
  for (int size : {1, 2, 5}) {
    const Planes a = render(size, size, 1, [](int, float x, float y) { return 0.1f * x + 0.2f * y; });
    const Planes b = render(size, size, 1, [](int, float x, float y) { return 0.1f * x + 0.2f * y + 0.05f; });
    const FlowField flow = computeFlow(a, b, FlowSettings{});
    ASSERT_EQ(flow.pixelCount(), a.pixelCount());
    for (size_t p = 0; p < flow.pixelCount(); ++p) {
      EXPECT_TRUE(std::isfinite(flow.dx[p]));
      EXPECT_TRUE(std::isfinite(flow.dy[p]));
    }
  }
}


}  // namespace
}  // namespace pathfarm
