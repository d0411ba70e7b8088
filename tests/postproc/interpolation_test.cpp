// Frame interpolation with re-render masks: depth decides splat conflicts, holes are
// masked, a rendered in-between frame is closer to the reference per component than with
// the beauty alone, and bad input is refused with the frame and layer named.
#include "postproc/interpolation/frame_interpolation.h"
#include "postproc/interpolation/feature_check.h"
#include "postproc/interpolation/irradiance_flow.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>

#include "postproc/metrics/image_metrics.h"
#include "renderer/integrators/frame_renderer.h"
#include "test_support.h"

namespace pathfarm {
namespace {

const char* const kComponentChannels[] = {"residual.color.R", "residual.color.G", "residual.color.B",
                                          "residual.depth.Z"};

// A one-component ("residual") frame with every value `color` at depth `depth`.
FrameImage flatFrame(int w, int h, float color, float depth) {
  FrameImage f(w, h);
  f.attributes()["pathfarm.decomposition"] = "residual";
  for (const char* c : {"R", "G", "B", "residual.color.R", "residual.color.G", "residual.color.B"})
    f.addChannel(c).assign(f.pixelCount(), color);
  f.addChannel("residual.depth.Z").assign(f.pixelCount(), depth);
  f.addChannel("depth.Z").assign(f.pixelCount(), depth);
  return f;
}

void setPixel(FrameImage& f, int x, int y, float color, float depth) {
  const size_t p = static_cast<size_t>(y * f.width() + x);
  for (const char* c : {"R", "G", "B", "residual.color.R", "residual.color.G", "residual.color.B"})
    f.channel(c)[p] = color;
  f.channel("residual.depth.Z")[p] = depth;
  f.channel("depth.Z")[p] = depth;
}

MotionField zeroField(int w, int h) {
  MotionField m;
  m.width = w;
  m.height = h;
  m.x.assign(static_cast<size_t>(w * h), 0.0f);
  m.y.assign(static_cast<size_t>(w * h), 0.0f);
  return m;
}

ComponentMotions motionsOf(const MotionField& forward, const MotionField& backward) {
  ComponentMotions m;
  m.components["residual"] = ComponentMotion{forward, backward};
  m.components[""] = ComponentMotion{forward, backward};
  return m;
}

// Object A (2x2, value 1) moves 4 px right between the keyframes over a static background
// (0.2, depth 10); static object B (2x2, value 0.5, depth 5) sits where A is at s = 0.5.
void depthCase(float depthA, float expected) {
  const int w = 12, h = 4;
  FrameImage k0 = flatFrame(w, h, 0.2f, 10.0f), k1 = flatFrame(w, h, 0.2f, 10.0f);
  MotionField forward = zeroField(w, h), backward = zeroField(w, h);
  for (int y = 1; y < 3; ++y) {
    for (int x : {4, 5}) {
      setPixel(k0, x, y, 0.5f, 5.0f);
      setPixel(k1, x, y, 0.5f, 5.0f);
    }
    for (int x : {2, 3}) {
      setPixel(k0, x, y, 1.0f, depthA);
      forward.x[static_cast<size_t>(y * w + x)] = 4.0f;
    }
    for (int x : {6, 7}) {
      setPixel(k1, x, y, 1.0f, depthA);
      backward.x[static_cast<size_t>(y * w + x)] = -4.0f;
    }
  }
  const InterpolationResult r = interpolateFrameDetailed(k0, k1, motionsOf(forward, backward), 0.5f);
  for (int y = 1; y < 3; ++y)
    for (int x : {4, 5}) EXPECT_NEAR(r.frame.channel("R")[static_cast<size_t>(y * w + x)], expected, 1e-5) << x << "," << y;
  EXPECT_EQ(r.holePixels, 0u);
}

TEST(Interpolation, SplatConflictsAreResolvedByDepth) {
  depthCase(1.0f, 1.0f);  // A in front of B: A
  depthCase(8.0f, 0.5f);  // A behind B: B
}

// A camera moving away: a surface 25 % farther in the second keyframe than in the first,
// beyond the depth test's tolerance. Taken at the in-between instant, both keyframes' depths
// are one surface's and both are blended; taken as each keyframe saw it, the first
// keyframe's would be nearer and win alone.
TEST(Interpolation, ASurfaceTheCameraMovesAwayFromIsOneSurfaceInBothKeyframes) {
  const int w = 16, h = 4;
  const FrameImage k0 = flatFrame(w, h, 1.0f, 2.0f), k1 = flatFrame(w, h, 2.0f, 2.5f);
  MotionField forward = zeroField(w, h), backward = zeroField(w, h);
  for (size_t p = 0; p < forward.x.size(); ++p) {
    forward.x[p] = 2.0f;
    backward.x[p] = -2.0f;
  }
  const InterpolationResult r = interpolateFrameDetailed(k0, k1, motionsOf(forward, backward), 0.5f);
  for (int y = 0; y < h; ++y)
    for (int x = 2; x < w - 2; ++x) {
      const size_t p = static_cast<size_t>(y * w + x);
      EXPECT_FLOAT_EQ(r.frame.channel("R")[p], 1.5f) << x << ", " << y;
      EXPECT_FLOAT_EQ(r.frame.channel("residual.depth.Z")[p], 2.25f) << x << ", " << y;
      EXPECT_EQ(r.mask[p], 0) << x << ", " << y;
    }
}

// A static floor under constant light whose texture edge the keyframes put one column left
// of where the in-between frame has it (in a shot: an edge the motion moves imprecisely).
// Given the frame's own features, a pixel within a pixel of the keyframes' edge is the
// interpolated irradiance times the frame's own reflectance; elsewhere, where the features'
// reflectance is a noisy estimate of the same, and where it is below the guard, the
// keyframes' reflectance is kept, as without features.
TEST(Interpolation, AtTextureEdgesTheInBetweenFramesOwnReflectanceModulatesItsIrradiance) {
  const int w = 12, h = 4, edge = 6;
  const float irradiance = 2.0f;
  const auto textured = [&](const std::function<float(int x, int y)>& reflectance) {
    FrameImage f(w, h);
    f.attributes()["pathfarm.decomposition"] = "residual";
    for (const char* c : {"R", "G", "B", "residual.color.R", "residual.color.G", "residual.color.B",
                          "residual.irradiance.R", "residual.irradiance.G", "residual.irradiance.B",
                          "residual.reflectance.R", "residual.reflectance.G", "residual.reflectance.B"})
      f.addChannel(c).assign(f.pixelCount(), 0.0f);
    f.addChannel("residual.depth.Z").assign(f.pixelCount(), 3.0f);
    f.addChannel("depth.Z").assign(f.pixelCount(), 3.0f);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t p = static_cast<size_t>(y * w + x);
        const float r = reflectance(x, y);
        for (const char* c : {"residual.reflectance.R", "residual.reflectance.G", "residual.reflectance.B"})
          f.channel(c)[p] = r;
        for (const char* c : {"residual.irradiance.R", "residual.irradiance.G", "residual.irradiance.B"})
          f.channel(c)[p] = irradiance;
        for (const char* c : {"R", "G", "B", "residual.color.R", "residual.color.G", "residual.color.B"})
          f.channel(c)[p] = irradiance * r;
      }
    return f;
  };
  const auto keyframeTexture = [&](int x, int) { return x < edge ? 0.2f : 0.8f; };
  const FrameImage k0 = textured(keyframeTexture), k1 = textured(keyframeTexture);
  // The frame's own texture: the edge a column to the right, with ±10 % of noise, and no
  // surface of the component at (edge - 1, 0).
  const FrameImage own = textured([&](int x, int y) {
    if (x == edge - 1 && y == 0) return 0.0f;
    return (x < edge + 1 ? 0.2f : 0.8f) * ((x + y) % 2 == 0 ? 1.1f : 0.9f);
  });
  const ComponentMotions motions = motionsOf(zeroField(w, h), zeroField(w, h));
  LayeredKeyframes keys = wholeKeyframes(k0, k1, motions);
  keys.inBetween = &own;
  const FrameImage modulated = interpolateFrameDetailed(keys, 0.25f).frame;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t p = static_cast<size_t>(y * w + x);
      const float ownReflectance = own.channel("residual.reflectance.G")[p];
      const bool atEdge = (x == edge - 1 || x == edge) && ownReflectance > 0.0f;
      const float expected = irradiance * (atEdge ? ownReflectance : keyframeTexture(x, y));
      EXPECT_FLOAT_EQ(modulated.channel("residual.color.G")[p], expected) << x << ", " << y;
      EXPECT_FLOAT_EQ(modulated.channel("G")[p], expected) << x << ", " << y;
    }
  // Features of another size are refused, with both sizes named.
  const FrameImage small(w / 2, h);
  keys.inBetween = &small;
  try {
    interpolateFrameDetailed(keys, 0.25f);
    ADD_FAILURE() << "features of another size were accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("6x4"), std::string::npos) << e.what();
  }
}

TEST(Interpolation, HolesAreInTheMask) {
  // Everything diverges from the middle column: nothing lands on the middle at s = 0.5.
  const int w = 16, h = 6;
  const FrameImage k0 = flatFrame(w, h, 0.5f, 3.0f), k1 = flatFrame(w, h, 0.5f, 3.0f);
  MotionField forward = zeroField(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) forward.x[static_cast<size_t>(y * w + x)] = x < 8 ? -4.0f : 4.0f;
  const InterpolationResult r = interpolateFrameDetailed(k0, k1, motionsOf(forward, forward), 0.5f);
  EXPECT_GT(r.holePixels, 0u);
  for (int y = 0; y < h; ++y) {
    for (int x = 7; x <= 8; ++x) EXPECT_EQ(r.holes[static_cast<size_t>(y * w + x)], 1) << x;
    EXPECT_EQ(r.holes[static_cast<size_t>(y * w + 2)], 0);
  }
  for (size_t p = 0; p < r.holes.size(); ++p) {
    if (r.holes[p]) {
      EXPECT_EQ(r.mask[p], 1);
    }
    EXPECT_EQ(r.frame.channel("rerender.Y")[p], static_cast<float>(r.mask[p]));
    EXPECT_FLOAT_EQ(r.frame.channel("R")[p], 0.5f);  // best effort: the static blend
  }
  EXPECT_GT(r.rerenderRate, 0.0);
  EXPECT_EQ(r.frame.attributes().at("pathfarm.rerender_rate").substr(0, 3), "0.2");  // 4 of 16 columns + edges
  // The same holes through the color-only baseline.
  InterpolationSettings colorOnly;
  colorOnly.colorOnly = true;
  const InterpolationResult c = interpolateFrameDetailed(k0, k1, motionsOf(forward, forward), 0.5f, colorOnly);
  EXPECT_EQ(c.holes, r.holes);
}

TEST(Interpolation, UntrackedAndSilhouettePixelsAreMasked) {
  const int w = 10, h = 4;
  FrameImage k0 = flatFrame(w, h, 0.5f, 3.0f), k1 = flatFrame(w, h, 0.5f, 3.0f);
  MotionField forward = zeroField(w, h), backward = zeroField(w, h);
  forward.valid.assign(static_cast<size_t>(w * h), 1.0f);
  forward.valid[static_cast<size_t>(1 * w + 2)] = 0.0f;  // an untracked specular pixel
  k1.addChannel("silhouette.Y")[static_cast<size_t>(2 * w + 6)] = 1.0f;
  backward.x[static_cast<size_t>(2 * w + 6)] = -2.0f;  // lands at x = 5 for s = 0.5
  const InterpolationResult r = interpolateFrameDetailed(k0, k1, motionsOf(forward, backward), 0.5f);
  EXPECT_EQ(r.mask[static_cast<size_t>(1 * w + 2)], 1);
  EXPECT_EQ(r.mask[static_cast<size_t>(2 * w + 5)], 1);
  EXPECT_EQ(r.untrackedPixels, 1u);
  EXPECT_EQ(r.silhouettePixels, 1u);
}

TEST(Interpolation, OneSidedLightWithNothingNearbyToCompareIsMaskedUnlessTheCallerChecksIt) {
  // A pan: everything moves 8 px left between the keyframes. At s = 0.5 the 4 columns on
  // each side are seen by one keyframe only, and the outer 2 have no pixel seen by both
  // within the illumination radius (2) to tell whether their light changed.
  const int w = 20, h = 6;
  const FrameImage k0 = flatFrame(w, h, 0.5f, 3.0f), k1 = flatFrame(w, h, 0.5f, 3.0f);
  MotionField forward = zeroField(w, h), backward = zeroField(w, h);
  for (size_t p = 0; p < forward.x.size(); ++p) {
    forward.x[p] = -8.0f;
    backward.x[p] = 8.0f;
  }
  const InterpolationResult masked = interpolateFrameDetailed(k0, k1, motionsOf(forward, backward), 0.5f);
  InterpolationSettings checkedElsewhere;
  checkedElsewhere.unknownChangeMasks = false;
  const InterpolationResult kept = interpolateFrameDetailed(k0, k1, motionsOf(forward, backward), 0.5f, checkedElsewhere);
  EXPECT_EQ(masked.illuminationPixels, static_cast<size_t>(4 * h));
  EXPECT_EQ(kept.illuminationPixels, 0u);
  for (int y = 0; y < h; ++y)
    for (const int x : {0, 1, w - 2, w - 1}) {
      const size_t p = static_cast<size_t>(y * w + x);
      EXPECT_EQ(masked.mask[p], 1) << x << ", " << y;
      EXPECT_EQ(kept.mask[p], 0) << x << ", " << y;
      EXPECT_FLOAT_EQ(kept.frame.channel("R")[p], 0.5f);  // the one keyframe's light
    }
}

TEST(Interpolation, BadInputIsRefusedWithTheFrameAndLayerNamed) {
  const FrameImage k0 = flatFrame(8, 4, 0.5f, 3.0f);
  const ComponentMotions motions = motionsOf(zeroField(8, 4), zeroField(8, 4));
  auto expectMessage = [](const auto& call, const std::string& needle) {
    try {
      call();
      ADD_FAILURE() << "no exception, expected " << needle;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expectMessage([&] { interpolateFrame(k0, flatFrame(9, 4, 0.5f, 3.0f), motions, 0.5f); }, "keyframe 1 is 9x4");
  expectMessage([&] { interpolateFrame(k0, k0, motions, 1.0f); }, "(0, 1)");
  expectMessage([&] { interpolateFrame(k0, k0, ComponentMotions{}, 0.5f); }, "component \"residual\"");
  expectMessage([&] { interpolateFrame(k0, k0, motionsOf(zeroField(8, 3), zeroField(8, 4)), 0.5f); },
                "forward motion of component \"residual\"");
  FrameImage broken = k0;
  broken.channel("residual.color.G")[5] = std::numeric_limits<float>::infinity();
  expectMessage([&] { interpolateFrame(k0, broken, motions, 0.5f); }, "keyframe 1: channel \"residual.color.G\"");
  FrameImage noDepth(8, 4);
  noDepth.attributes() = k0.attributes();
  for (const std::string& n : k0.channelNames())
    if (n != "residual.depth.Z") noDepth.addChannel(n) = k0.channel(n);
  expectMessage([&] { interpolateFrame(noDepth, k0, motions, 0.5f); }, "keyframe 0: missing channel \"residual.depth.Z\"");
  // Concatenation: missing motion layers and too few frames.
  expectMessage([&] { concatenatePrimaryMotion({k0, k0}); }, "frame 0: missing channel \"motion.X\"");
  expectMessage([&] { concatenatePrimaryMotion({k0}); }, "at least two frames");
  (void)kComponentChannels;
}

TEST(Interpolation, ConcatenatesMotionAlongTheChain) {
  // Three frames; frame 0 moves everything +1.5 px in x, frame 1 moves pixels right of x = 5
  // by +2 and the rest by +1: a pixel at x = 4 goes 5.5 (bilinear: 1.5 of +2 and +1) ...
  const int w = 12, h = 2;
  std::vector<FrameImage> frames;
  for (int k = 0; k < 3; ++k) {
    FrameImage f = flatFrame(w, h, 0.5f, 3.0f);
    for (const char* c : {"motion.X", "motion.Y", "motion_back.X", "motion_back.Y", "residual.motion.X",
                          "residual.motion.Y", "residual.motion_back.X", "residual.motion_back.Y",
                          "residual.motion_valid.Y"})
      f.addChannel(c);
    for (int x = 0; x < w; ++x)
      for (int y = 0; y < h; ++y) {
        const size_t p = static_cast<size_t>(y * w + x);
        const float m = k == 0 ? 1.5f : (x > 5 ? 2.0f : 1.0f);
        f.channel("motion.X")[p] = f.channel("residual.motion.X")[p] = m;
        f.channel("motion_back.X")[p] = f.channel("residual.motion_back.X")[p] = -1.0f;
        f.channel("residual.motion_valid.Y")[p] = k == 1 && x == 7 ? 0.0f : 1.0f;
      }
    frames.push_back(f);
  }
  const ComponentMotions m = concatenatePrimaryMotion(frames);
  const ComponentMotion& r = m.components.at("residual");
  // x = 1 -> 2.5 (links 1 and 2 blended at 2.5: +1) -> 3.5.
  EXPECT_FLOAT_EQ(r.forward.x[1], 2.5f);
  // x = 5 -> 6.5 (+2) -> 8.5, but it passes x = 7's invalid link? 6.5 rounds to 7 (nearest).
  EXPECT_EQ(r.forward.valid[5], 0.0f);
  // x = 4 -> 5.5: half of +1 and +2.
  EXPECT_FLOAT_EQ(r.forward.x[4], 3.0f);
  // Leaving the image is invalid: x = 9 -> 10.5 -> 12.5.
  EXPECT_EQ(r.forward.valid[9], 0.0f);
  EXPECT_EQ(r.forward.valid[1], 1.0f);
  EXPECT_FLOAT_EQ(r.backward.x[5], -2.0f);
  EXPECT_EQ(r.backward.valid[1], 0.0f);  // 1 -> 0 -> -1
  EXPECT_TRUE(m.components.at("").forward.valid[5] == 1.0f);  // the frame-wide motion has no validity plane
}

// A still mirror (component "mirror") at depth 2 showing a surface at path length 5, its
// motion tracked by the walk. The interpolated mirror keeps the depth of what it shows,
// which the frame's own features then agree with; taken from the frame-wide depth.Z (the
// mirror's own surface), the feature check flagged every mirror and glass pixel under a
// moving camera.
TEST(Interpolation, ASpecularComponentKeepsTheDepthOfWhatItShows) {
  const int w = 8, h = 4;
  const auto mirrorFrame = [&](bool listsSpecular) {
    FrameImage f = flatFrame(w, h, 0.0f, 2.0f);
    f.attributes()["pathfarm.decomposition"] = "mirror=ERD.*,residual";
    if (listsSpecular) f.attributes()["pathfarm.specular_components"] = "mirror";
    for (const char* c : {"R", "G", "B", "mirror.color.R", "mirror.color.G", "mirror.color.B"})
      f.addChannel(c).assign(f.pixelCount(), 1.0f);
    f.addChannel("mirror.depth.Z").assign(f.pixelCount(), 5.0f);
    f.addChannel("mirror.motion_valid.Y").assign(f.pixelCount(), 1.0f);
    f.addChannel("mirror.normal.X");
    f.addChannel("mirror.normal.Y").assign(f.pixelCount(), 1.0f);
    f.addChannel("mirror.normal.Z");
    for (const char* c : {"residual.normal.X", "residual.normal.Y", "residual.normal.Z"}) f.addChannel(c);
    return f;
  };
  ComponentMotions motions = motionsOf(zeroField(w, h), zeroField(w, h));
  motions.components["mirror"] = motions.components.at("residual");
  for (const bool listsSpecular : {true, false}) {
    const FrameImage key = mirrorFrame(listsSpecular);
    const InterpolationResult r = interpolateFrameDetailed(key, key, motions, 0.5f);
    const std::vector<uint8_t> mismatch = featureMismatch(r.frame, mirrorFrame(true));
    const float expectedDepth = listsSpecular ? 5.0f : 2.0f;  // without the attribute: as before
    for (size_t p = 0; p < r.frame.pixelCount(); ++p) {
      ASSERT_FLOAT_EQ(r.frame.channel("mirror.depth.Z")[p], expectedDepth) << p;
      ASSERT_EQ(mismatch[p], listsSpecular ? 0 : 1) << p;
    }
  }
}

// A soft shadow moving 4 px to the right over a static floor (zero primary motion): with the
// irradiance flow the shadow of the in-between frame is halfway, not cross-faded.
TEST(Interpolation, IrradianceFollowsItsFlowOverAStaticSurface) {
  const int w = 32, h = 32;
  const float reflectance = 0.5f;
  auto frame = [&](float cx) {
    FrameImage f(w, h);
    f.attributes()["pathfarm.decomposition"] = "residual";
    for (const char* c : {"R", "G", "B", "residual.color.R", "residual.color.G", "residual.color.B",
                          "residual.irradiance.R", "residual.irradiance.G", "residual.irradiance.B"})
      f.addChannel(c).assign(f.pixelCount(), 0.0f);
    for (const char* c : {"residual.reflectance.R", "residual.reflectance.G", "residual.reflectance.B"})
      f.addChannel(c).assign(f.pixelCount(), reflectance);
    f.addChannel("residual.depth.Z").assign(f.pixelCount(), 5.0f);
    f.addChannel("depth.Z").assign(f.pixelCount(), 5.0f);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t p = static_cast<size_t>(y * w + x);
        const float dx = static_cast<float>(x) - cx, dy = static_cast<float>(y) - 16.0f;
        const float e = 1.0f - 0.9f * std::exp(-(dx * dx + dy * dy) / 18.0f);
        for (const char* c : {"residual.irradiance.R", "residual.irradiance.G", "residual.irradiance.B"})
          f.channel(c)[p] = e;
        for (const char* c : {"R", "G", "B", "residual.color.R", "residual.color.G", "residual.color.B"})
          f.channel(c)[p] = e * reflectance;
      }
    return f;
  };
  const FrameImage k0 = frame(12.0f), k1 = frame(16.0f);
  ComponentMotions motions;
  MotionField still;
  still.width = w;
  still.height = h;
  still.x.assign(k0.pixelCount(), 0.0f);
  still.y.assign(k0.pixelCount(), 0.0f);
  motions.components["residual"] = ComponentMotion{still, still};
  motions.components[""] = ComponentMotion{still, still};
  const FrameImage crossFaded = interpolateFrame(k0, k1, motions, 0.5f);
  addIrradianceFlow(motions, k0, k1, FlowSettings{});
  ASSERT_TRUE(motions.components.at("residual").hasIrradianceMotion);
  EXPECT_FALSE(motions.components.at("").hasIrradianceMotion);
  const size_t centre = static_cast<size_t>(16 * w + 14);
  EXPECT_NEAR(motions.components.at("residual").irradianceForward.x[centre], 4.0f, 0.5f);
  EXPECT_NEAR(motions.components.at("residual").irradianceBackward.x[centre + 2], -4.0f, 0.5f);
  const FrameImage tracked = interpolateFrame(k0, k1, motions, 0.5f);
  const FrameImage expected = frame(14.0f);
  // Cross-fading leaves two half shadows; the tracked shadow is the one at x = 14.
  EXPECT_GT(crossFaded.channel("R")[centre], expected.channel("R")[centre] + 0.05f);
  EXPECT_NEAR(tracked.channel("R")[centre], expected.channel("R")[centre], 0.02f);
  EXPECT_NEAR(tracked.channel("residual.color.G")[centre], expected.channel("residual.color.G")[centre], 0.02f);
}

double relMseOf(const FrameImage& image, const FrameImage& reference) {
  return compareImages(image, reference, {"R", "G", "B"}).relMse;
}

// The Cornell box, frames 0..4 at 64x64 and 16 spp with the default decomposition; frame 2
// interpolated from 0 and 4 against a 256-spp render of frame 2. Per component with the
// irradiance along its flow (addIrradianceFlow); the color-only baseline along the primary
// motion.
TEST(Interpolation, PerComponentBeatsColorOnlyOnARenderedSequence) {
  const Scene scene = loadScene(test_support::sourceDir() / "scenes/cornell/scene.json");
  RenderSettings settings;
  settings.width = 64;
  settings.height = 64;
  settings.spp = 256;
  const FrameImage reference = FrameRenderer(scene, settings).render(2);
  settings.spp = 16;
  settings.decomposition = std::make_shared<Decomposition>(Decomposition::standard());
  const FrameRenderer renderer(scene, settings);
  std::vector<FrameImage> frames;
  for (int k = 0; k <= 4; ++k) frames.push_back(renderer.render(k));
  const ComponentMotions motions = concatenatePrimaryMotion(frames);
  // The paper's scheme: each component's irradiance along its optical flow between the
  // keyframes, its reflectance along the primary motion.
  ComponentMotions withIrradiance = motions;
  addIrradianceFlow(withIrradiance, frames[0], frames[4], FlowSettings{});
  const InterpolationResult perComponent = interpolateFrameDetailed(frames[0], frames[4], withIrradiance, 0.5f);
  InterpolationSettings baseline;
  baseline.colorOnly = true;
  const InterpolationResult colorOnly = interpolateFrameDetailed(frames[0], frames[4], motions, 0.5f, baseline);

  // relMSE over the pixels neither mask sends to re-rendering: the others are re-rendered.
  FrameImage masked = reference;
  for (const char* c : {"R", "G", "B"})
    for (size_t p = 0; p < masked.pixelCount(); ++p)
      if (perComponent.mask[p] || colorOnly.mask[p]) masked.channel(c)[p] = std::numeric_limits<float>::quiet_NaN();
  const double componentError = relMseOf(perComponent.frame, masked), colorError = relMseOf(colorOnly.frame, masked);
  const double componentAll = relMseOf(perComponent.frame, reference), colorAll = relMseOf(colorOnly.frame, reference);
  std::printf("re-render rate: per-component %.4f (holes %zu, silhouettes %zu, untracked %zu, illumination %zu), "
              "color-only %.4f\n",
              perComponent.rerenderRate, perComponent.holePixels, perComponent.silhouettePixels,
              perComponent.untrackedPixels, perComponent.illuminationPixels, colorOnly.rerenderRate);
  std::printf("relMSE unmasked: per-component %.5f, color-only %.5f; all pixels: %.5f, %.5f; keyframe 0 %.5f\n",
              componentError, colorError, componentAll, colorAll, relMseOf(frames[0], reference));
  RecordProperty("rerender_rate", std::to_string(perComponent.rerenderRate));
  EXPECT_LT(componentError, colorError);
  for (size_t p = 0; p < perComponent.holes.size(); ++p)
    if (perComponent.holes[p]) {
      ASSERT_EQ(perComponent.mask[p], 1) << p;
    }
  EXPECT_EQ(perComponent.frame.attributes().at("pathfarm.rerender_rate").substr(0, 1), "0");
}

}  // namespace
}  // namespace pathfarm
