// Denoising decomposed frames: per-component filtering beats filtering the beauty on a
// rendered frame with a mirror, neighbour frames help when warped along the right
// motion, and broken input gives a clear error or a counted skip.
#include "postproc/filters/component_denoiser.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <random>

#include "postproc/metrics/relmse.h"
#include "renderer/decomposition/effective_irradiance.h"
#include "renderer/integrators/frame_renderer.h"
#include "test_support.h"

namespace pathfarm {
namespace {

const char* const kRgb[] = {"R", "G", "B"};

// A shot of one diffuse component moving right by `speed` pixels per frame: stripes of
// three objects (each its reflectance and normal) under smooth illumination (but for a
// shadow on one object), with
// Gaussian noise of standard deviation `sigma` (the variance planes say so). The
// residual is zero.
struct SyntheticShot {
  int width = 64, height = 48, speed = 2;
  float sigma = 0.08f;
  bool motionValid = true;

  // Smooth light, and a sharp shadow over the second object.
  float irradiance(int world, int y) const {
    const float light = 0.5f + 0.2f * std::sin(static_cast<float>(world) / 11.0f) +
                        0.2f * static_cast<float>(y) / static_cast<float>(height);
    return object(world) == 1 ? 0.35f * light : light;
  }
  static int object(int world) { return (world / 16) % 3; }
  static float reflectance(int object, int c) {
    static const float table[3][3] = {{0.8f, 0.3f, 0.2f}, {0.2f, 0.7f, 0.3f}, {0.5f, 0.5f, 0.9f}};
    return table[object][c];
  }

  // Frame `t`; `noiseSeed` 0 gives the noise-free truth.
  FrameImage frame(int t, uint32_t noiseSeed) const {
    FrameImage f(width, height);
    f.attributes()["pathfarm.decomposition"] = "diffuse=ED,residual";
    std::mt19937 rng(noiseSeed);
    std::normal_distribution<float> noise(0.0f, sigma);
    for (const char* component : {"diffuse", "residual"}) {
      const std::string c = component;
      for (const char* b : {".color.", ".variance.", ".reflectance.", ".irradiance."})
        for (const char* ch : kRgb) f.addChannel(c + b + ch);
      for (const char* ch : {"X", "Y", "Z"}) f.addChannel(c + ".normal." + ch);
      f.addChannel(c + ".objectid.Y");
      f.addChannel(c + ".depth.Z");
      for (const char* ch : {"X", "Y"}) {
        f.addChannel(c + ".motion." + ch);
        f.addChannel(c + ".motion_back." + ch);
      }
      f.addChannel(c + ".motion_valid.Y");
    }
    for (const char* ch : kRgb) {
      f.addChannel(ch);
      f.addChannel(std::string("variance.") + ch);
    }
    for (const char* ch : {"X", "Y"}) {
      f.addChannel(std::string("motion.") + ch);
      f.addChannel(std::string("motion_back.") + ch);
    }
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const size_t p = static_cast<size_t>(y * width + x);
        const int world = x - speed * t + 1000;
        const int id = object(world);
        for (int c = 0; c < 3; ++c) {
          const float r = reflectance(id, c);
          float color = irradiance(world, y) * r;
          if (noiseSeed != 0) color += noise(rng);
          f.channel(std::string("diffuse.color.") + kRgb[c])[p] = color;
          f.channel(std::string("diffuse.variance.") + kRgb[c])[p] = noiseSeed != 0 ? sigma * sigma : 0.0f;
          f.channel(std::string("diffuse.reflectance.") + kRgb[c])[p] = r;
          f.channel(std::string("diffuse.irradiance.") + kRgb[c])[p] = effectiveIrradiance(color, r);
          f.channel(kRgb[c])[p] = color;
          f.channel(std::string("variance.") + kRgb[c])[p] = noiseSeed != 0 ? sigma * sigma : 0.0f;
        }
        f.channel("diffuse.normal.X")[p] = 0.3f * static_cast<float>(id - 1);
        f.channel("diffuse.normal.Z")[p] = 1.0f;
        f.channel("diffuse.objectid.Y")[p] = static_cast<float>(id + 1);
        f.channel("diffuse.depth.Z")[p] = 3.0f;
        for (const char* prefix : {"diffuse.", ""}) {
          f.channel(std::string(prefix) + "motion.X")[p] = static_cast<float>(speed);
          f.channel(std::string(prefix) + "motion_back.X")[p] = -static_cast<float>(speed);
        }
        f.channel("diffuse.motion_valid.Y")[p] = motionValid ? 1.0f : 0.0f;
      }
    }
    return f;
  }
};

TEST(ComponentDenoiser, SpatioTemporalDenoisingUsesTheWarpedNeighbours) {
  const SyntheticShot shot;
  const FrameImage truth = shot.frame(0, 0);
  const FrameImage previous = shot.frame(-1, 11), current = shot.frame(0, 12), next = shot.frame(1, 13);
  DenoiseSettings s;
  s.spatialRadius = 5;  // the same window per frame as the temporal radius
  const double noisy = relMse(current, truth);
  const FrameImage spatial = denoiseFrame(current, nullptr, nullptr, s);
  const FrameImage temporal = denoiseFrame(current, &previous, &next, s);
  const double spatialError = relMse(spatial, truth), temporalError = relMse(temporal, truth);
  EXPECT_LT(spatialError * 4, noisy);
  EXPECT_LT(temporalError, spatialError) << "noisy " << noisy;

  // The same neighbours claimed still (motion 0): features and colors no longer line up.
  FrameImage still = current;
  for (const char* name : {"diffuse.motion.X", "diffuse.motion_back.X"})
    std::fill(still.channel(name).begin(), still.channel(name).end(), 0.0f);
  EXPECT_LT(temporalError, relMse(denoiseFrame(still, &previous, &next, s), truth));

  // Components add up to the beauty, and the output says what was done.
  for (size_t p = 0; p < temporal.pixelCount(); p += 37)
    EXPECT_NEAR(temporal.channel("R")[p],
                temporal.channel("diffuse.color.R")[p] + temporal.channel("residual.color.R")[p], 1e-6f);
  EXPECT_EQ(temporal.channel("residual.color.G"), std::vector<float>(temporal.pixelCount(), 0.0f));
  EXPECT_EQ(temporal.attributes().at("pathfarm.denoise_skipped"), "0");
  EXPECT_NE(temporal.attributes().at("pathfarm.denoise").find("mode=decomposition frames=3"), std::string::npos);
  EXPECT_EQ(temporal.attributes().at("pathfarm.decomposition"), "diffuse=ED,residual");
}

TEST(ComponentDenoiser, NeighboursWithoutValidMotionAreDropped) {
  SyntheticShot shot;
  shot.motionValid = false;
  const FrameImage previous = shot.frame(-1, 11), current = shot.frame(0, 12), next = shot.frame(1, 13);
  const DenoiseSettings s;
  // No valid pixel in either neighbour: a spatial filter with the spatial radius, bit for bit.
  EXPECT_EQ(denoiseFrame(current, &previous, &next, s).channel("G"),
            denoiseFrame(current, nullptr, nullptr, s).channel("G"));
}

TEST(ComponentDenoiser, BaselinesRunThroughTheSameCode) {
  const SyntheticShot shot;
  const FrameImage truth = shot.frame(0, 0), current = shot.frame(0, 5);
  DenoiseSettings s;
  const double noisy = relMse(current, truth);
  const double decomposed = relMse(denoiseFrame(current, nullptr, nullptr, s), truth);
  s.mode = DenoiseMode::DecompositionWithoutFeatures;
  const FrameImage withoutFeatures = denoiseFrame(current, nullptr, nullptr, s);
  s.mode = DenoiseMode::ColorOnly;
  const FrameImage colorOnly = denoiseFrame(current, nullptr, nullptr, s);
  EXPECT_LT(decomposed, relMse(withoutFeatures, truth));
  EXPECT_LT(relMse(colorOnly, truth), noisy);
  EXPECT_TRUE(withoutFeatures.hasChannel("diffuse.color.R"));
  EXPECT_FALSE(colorOnly.hasChannel("diffuse.color.R"));

  // The color-only mode filters frames without a decomposition too.
  FrameImage plain(current.width(), current.height());
  for (const char* ch : kRgb) {
    plain.addChannel(ch) = current.channel(ch);
    plain.addChannel(std::string("variance.") + ch) = current.channel(std::string("variance.") + ch);
  }
  EXPECT_LT(relMse(denoiseFrame(plain, nullptr, nullptr, s), truth), noisy);

  EXPECT_EQ(parseDenoiseMode("no-features"), DenoiseMode::DecompositionWithoutFeatures);
  EXPECT_EQ(denoiseModeName(parseDenoiseMode("color")), "color");
  EXPECT_THROW(parseDenoiseMode("fast"), std::invalid_argument);
}

// Adds `light` to every channel of the diffuse component at (x, y), as one bright sample
// would: its variance is its value squared.
void addFirefly(FrameImage& frame, int x, int y, float light) {
  const size_t p = static_cast<size_t>(y * frame.width() + x);
  for (const char* ch : kRgb) {
    const std::string c(ch);
    const float color = frame.channel("diffuse.color." + c)[p] + light;
    frame.channel("diffuse.color." + c)[p] = color;
    frame.channel("diffuse.variance." + c)[p] = color * color;
    frame.channel("diffuse.irradiance." + c)[p] =
        effectiveIrradiance(color, frame.channel("diffuse.reflectance." + c)[p]);
    frame.channel(c)[p] += light;
    frame.channel("variance." + c)[p] = color * color;
  }
}

TEST(ComponentDenoiser, AFireflyLeavesNoSquareAndKeepsItsLight) {
  SyntheticShot shot;
  shot.sigma = 0.02f;
  const FrameImage clean = shot.frame(0, 12);
  FrameImage withFirefly = clean;
  constexpr int kX = 16, kY = 24, kStripe0 = 8, kStripe1 = 24;  // the firefly's object: x in [8, 24)
  addFirefly(withFirefly, kX, kY, 4.0f);
  // What the firefly adds to the denoised frame: its light, and the largest step between
  // two pixels of its stripe relative to the largest addition (the firefly itself left out).
  struct Added {
    double light = 0;
    float peak = 0, step = 0;
  };
  const auto addedBy = [&](const DenoiseSettings& s) {
    const FrameImage a = denoiseFrame(withFirefly, nullptr, nullptr, s), b = denoiseFrame(clean, nullptr, nullptr, s);
    const auto change = [&](int x, int y) {
      const size_t p = static_cast<size_t>(y * shot.width + x);
      return x == kX && y == kY ? 0.0f : a.channel("G")[p] - b.channel("G")[p];
    };
    Added added;
    for (int y = 0; y < shot.height; ++y)
      for (int x = 0; x < shot.width; ++x) {
        const size_t p = static_cast<size_t>(y * shot.width + x);
        added.light += a.channel("G")[p] - b.channel("G")[p];
        if (x < kStripe0 || x >= kStripe1) continue;
        added.peak = std::max(added.peak, change(x, y));
        const bool beside = std::abs(x - kX) <= 1 && std::abs(y - kY) <= 1;  // steps to the firefly itself
        if (x + 1 < kStripe1 && !beside) added.step = std::max(added.step, std::abs(change(x + 1, y) - change(x, y)));
        if (y + 1 < shot.height && !beside) added.step = std::max(added.step, std::abs(change(x, y + 1) - change(x, y)));
      }
    return added;
  };
  DenoiseSettings s;
  const Added spread = addedBy(s);
  s.spreadFireflies = false;
  const Added filtered = addedBy(s);
  // The light stays, spread by a Gaussian (sigma r / 2, cut at r), whose steps between
  // neighbours reach at most 14 % of its peak, where it is cut.
  EXPECT_NEAR(spread.light, 4.0, 0.2);
  EXPECT_LT(spread.step, 0.2f * spread.peak);
  // Filtered with the frame, the firefly is taken in by every pixel whose search window
  // holds it: a flat box with sharp edges.
  EXPECT_GT(filtered.step, 0.5f * filtered.peak);
  EXPECT_EQ(denoiseFrame(withFirefly, nullptr, nullptr, DenoiseSettings{}).attributes().at("pathfarm.denoise_fireflies"),
            "1");
}

std::string errorOf(const std::function<void()>& call) {
  try {
    call();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ComponentDenoiser, BadInputGivesAClearErrorOrACountedSkip) {
  const SyntheticShot shot;
  DenoiseSettings s;
  s.label = "frame.exr";
  s.previousLabel = "frame_0009.exr";
  const FrameImage current = shot.frame(0, 5);

  // A missing layer, named with its frame.
  FrameImage missing(current.width(), current.height());
  for (const std::string& name : current.channelNames())
    if (name != "diffuse.normal.X") missing.addChannel(name) = current.channel(name);
  missing.attributes() = current.attributes();
  EXPECT_EQ(errorOf([&] { denoiseFrame(missing, nullptr, nullptr, s); }),
            "frame.exr: missing channel \"diffuse.normal.X\"");
  EXPECT_EQ(errorOf([&] { denoiseFrame(current, &missing, nullptr, s); }),
            "frame_0009.exr: missing channel \"diffuse.normal.X\"");
  s.mode = DenoiseMode::DecompositionWithoutFeatures;  // needs no normal
  EXPECT_EQ(errorOf([&] { denoiseFrame(missing, nullptr, nullptr, s); }), "(no error)");
  s.mode = DenoiseMode::Decomposition;

  // A frame without a decomposition in a decomposition mode.
  FrameImage undecomposed = current;
  undecomposed.attributes().clear();
  EXPECT_NE(errorOf([&] {
              denoiseFrame(undecomposed, nullptr, nullptr, s);
            }).find("frame.exr: no \"pathfarm.decomposition\""),
            std::string::npos);

  // Frames of different sizes.
  SyntheticShot smaller = shot;
  smaller.width = 32;
  const FrameImage small = smaller.frame(-1, 3);
  EXPECT_EQ(errorOf([&] { denoiseFrame(current, &small, nullptr, s); }), "frame_0009.exr is 32x48, frame.exr is 64x48");

  // NaN and infinite pixels: filtered from their neighbours, counted, never spread.
  FrameImage broken = current;
  broken.channel("diffuse.irradiance.G")[100] = std::numeric_limits<float>::quiet_NaN();
  broken.channel("diffuse.variance.B")[100] = std::numeric_limits<float>::infinity();  // the same pixel
  broken.channel("diffuse.variance.R")[700] = std::numeric_limits<float>::quiet_NaN();
  broken.channel("diffuse.reflectance.R")[900] = std::numeric_limits<float>::quiet_NaN();
  FrameImage brokenNeighbour = shot.frame(-1, 6);
  for (float& v : brokenNeighbour.channel("diffuse.irradiance.R")) v = std::numeric_limits<float>::quiet_NaN();
  for (const FrameImage* previous : std::vector<const FrameImage*>{nullptr, &brokenNeighbour}) {
    const FrameImage out = denoiseFrame(broken, previous, nullptr, s);
    EXPECT_EQ(out.attributes().at("pathfarm.denoise_skipped"), "2");
    for (const char* ch : kRgb)
      for (float v : out.channel(ch)) ASSERT_TRUE(std::isfinite(v));
    // The broken pixel is filled like its neighbours (the light is smooth there).
    EXPECT_NEAR(out.channel("G")[100], 0.5f * (out.channel("G")[99] + out.channel("G")[101]), 0.02f);
  }
  s.mode = DenoiseMode::ColorOnly;
  FrameImage brokenBeauty = current;
  brokenBeauty.channel("R")[5] = -std::numeric_limits<float>::infinity();
  EXPECT_EQ(denoiseFrame(brokenBeauty, nullptr, nullptr, s).attributes().at("pathfarm.denoise_skipped"), "1");
}

// Cornell box frame 0 at 64x64: 8 spp decomposed against a 512-spp reference.
TEST(ComponentDenoiser, DecomposedDenoiseBeatsColorOnlyOnARenderedFrame) {
  const Scene scene = loadScene(test_support::sourceDir() / "scenes/cornell/scene.json");
  RenderSettings settings;
  settings.width = 64;
  settings.height = 64;
  settings.spp = 512;
  settings.maxDepth = 8;
  const FrameImage reference = FrameRenderer(scene, settings).render(0);
  settings.spp = 8;
  settings.decomposition = std::make_shared<Decomposition>(Decomposition::standard());
  const FrameImage noisy = FrameRenderer(scene, settings).render(0);

  DenoiseSettings s;
  s.label = "cornell frame 0";
  const FrameImage decomposed = denoiseFrame(noisy, nullptr, nullptr, s);
  s.mode = DenoiseMode::ColorOnly;
  const FrameImage colorOnly = denoiseFrame(noisy, nullptr, nullptr, s);
  const double noisyError = relMse(noisy, reference), decomposedError = relMse(decomposed, reference),
               colorError = relMse(colorOnly, reference);
  RecordProperty("relmse_noisy", std::to_string(noisyError));
  RecordProperty("relmse_color_only", std::to_string(colorError));
  RecordProperty("relmse_decomposed", std::to_string(decomposedError));
  std::printf("relMSE noisy %.5f, color-only %.5f, decomposed %.5f\n", noisyError, colorError, decomposedError);
  EXPECT_LT(decomposedError, colorError);
  EXPECT_LT(colorError, noisyError);
}

}  // namespace
}  // namespace pathfarm

namespace pathfarm {
namespace {

// Rows [first, end) of frames[1] denoised apart with frames[0] and frames[2], as a
// window's task does: the rows of the current frame within denoiseReach, the neighbours'
// rows denoiseNeighbourRows names (or, when not `followMotion`, the current frame's own),
// and the neighbours that the whole frame's motion reaches (or only the window's rows').
FrameImage denoisedWindow(const std::vector<FrameImage>& frames, int first, int end, bool followMotion,
                          bool reachedFromWholeFrame) {
  const int width = frames[1].width(), height = frames[1].height();
  DenoiseSettings s;
  DenoiseWindow& window = s.window.emplace();
  window.frameHeight = height;
  window.first = first;
  window.end = end;
  window.currentTop = std::max(0, first - denoiseReach(s));
  const int currentEnd = std::min(height, end + denoiseReach(s));
  const FrameImage current = frames[1].crop(0, window.currentTop, width, currentEnd - window.currentTop);
  const FrameImage& judged = reachedFromWholeFrame ? frames[1] : current;
  const int judgedTop = reachedFromWholeFrame ? 0 : window.currentTop;
  window.previousReached = neighbourLayersReaching(judged, NeighbourFrame::Previous, judgedTop, height, s);
  window.nextReached = neighbourLayersReaching(judged, NeighbourFrame::Next, judgedTop, height, s);
  const auto rowsOf = [&](const FrameImage& frame, NeighbourFrame which, int& top) {
    auto [from, to] = std::pair{window.currentTop, currentEnd};
    if (followMotion) std::tie(from, to) = denoiseNeighbourRows(current, which, s);
    if (from >= to) std::tie(from, to) = std::pair{0, 1};
    top = from;
    return frame.crop(0, from, width, to - from);
  };
  const FrameImage previous = rowsOf(frames[0], NeighbourFrame::Previous, window.previousTop);
  const FrameImage next = rowsOf(frames[2], NeighbourFrame::Next, window.nextTop);
  return denoiseFrame(current, &previous, &next, s);
}

void expectSameFrame(const FrameImage& rows, const FrameImage& expected) {
  ASSERT_EQ(rows.channelNames(), expected.channelNames());
  for (const std::string& name : expected.channelNames()) ASSERT_EQ(rows.channel(name), expected.channel(name)) << name;
}

// Rows of a frame denoised apart, given the rows denoiseReach and denoiseNeighbourRows name
// and which neighbours the whole frame's motion reaches, are the whole frame's rows, bit
// for bit, with the counts of those rows. The light moves 100 rows a frame, so the
// neighbours' rows lie far from the window's, and a firefly sits above the window. Read at
// the window's own rows instead, the neighbours give other bits. Where no pixel near the
// window has valid motion, its neighbours still take part, as the rest of the frame's
// motion reaches them; judged from the window's rows alone they would not, and the filter
// would search farther (its spatial radius).
TEST(ComponentDenoiser, AWindowOfRowsIsTheWholeFramesRows) {
  constexpr int kFirst = 150, kEnd = 180, kMotionRows = 100;
  SyntheticShot shot;
  shot.width = 32;
  shot.height = 300;
  std::vector<FrameImage> frames = {shot.frame(-1, 11), shot.frame(0, 12), shot.frame(1, 13)};
  for (FrameImage& frame : frames)
    for (const std::string prefix : {"diffuse.", ""}) {
      std::fill(frame.channel(prefix + "motion.Y").begin(), frame.channel(prefix + "motion.Y").end(),
                static_cast<float>(kMotionRows));
      std::fill(frame.channel(prefix + "motion_back.Y").begin(), frame.channel(prefix + "motion_back.Y").end(),
                -static_cast<float>(kMotionRows));
    }
  addFirefly(frames[1], 10, kFirst - 20, 60.0f);
  const auto wholeRows = [&] {
    const FrameImage whole = denoiseFrame(frames[1], &frames[0], &frames[2], DenoiseSettings{});
    return whole.crop(0, kFirst, shot.width, kEnd - kFirst);
  };
  const FrameImage expected = wholeRows();
  const FrameImage rows = denoisedWindow(frames, kFirst, kEnd, true, true);
  expectSameFrame(rows, expected);
  EXPECT_EQ(rows.attributes().at("pathfarm.denoise_fireflies"), "0") << "the firefly is above the window";
  EXPECT_NE(denoisedWindow(frames, kFirst, kEnd, false, true).channel("G"), expected.channel("G"));

  // No valid motion within 120 rows of the window; the frame's first rows have some.
  std::vector<float>& valid = frames[1].channel("diffuse.motion_valid.Y");
  std::fill(valid.begin() + (kFirst - 120) * shot.width, valid.end(), 0.0f);
  const FrameImage unreached = wholeRows();
  expectSameFrame(denoisedWindow(frames, kFirst, kEnd, true, true), unreached);
  EXPECT_NE(denoisedWindow(frames, kFirst, kEnd, true, false).channel("G"), unreached.channel("G"));
}

}  // namespace
}  // namespace pathfarm
