// Point, spot and directional lights over a diffuse floor, against the closed form of the
// light they put on it, integrated outside the renderer: the path tracer, bdpt, the
// gradient-domain renderer and the three Metropolis methods must agree with it. The
// camera looks straight down at the floor, so its film maps linearly onto a square of the
// floor and a frame's mean is the mean radiance over that square.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "renderer/bidirectional/bdpt_frame_renderer.h"
#include "renderer/integrators/frame_renderer.h"
#include "renderer/integrators/gradient_frame_renderer.h"
#include "renderer/metropolis/metropolis_renderer.h"
#include "test_support.h"
#include "tests/renderer/lights/lit_floor.h"
#include "tests/renderer/metropolis/metropolis_test_support.h"

namespace pathfarm {
namespace {

constexpr double kFloorAlbedo = 0.5;
constexpr double kFloorPi = test_support::kLitFloorPi;
// The camera 2 above the floor with a 40 degree field of view sees |x|, |z| <= 2 tan 20.
const double kHalfWidth = 2 * std::tan(20 * kFloorPi / 180);

Scene floorLitBy(const std::string& light) {
  return test_support::sceneFromJson(R"({
    "camera": {"position": [0, 2, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": 40, "shutter": [0, 0.5]},
    "materials": {"floor": {"type": "diffuse", "reflectance": 0.5}},
    "lights": [)" + light + R"(],
    "shapes": [{"type": "rectangle", "size": [200, 200], "material": "floor",
                "transform": {"rotate": {"axis": [1, 0, 0], "angle": -90}}}]})");
}

double meanOverSquare(const std::function<double(double, double)>& radiance) {
  return test_support::meanOverSquare(kHalfWidth, radiance);
}

double pointRadiance(double x, double z, double lx, double h, double lz, double intensity, double falloff = 1) {
  return test_support::pointLitRadiance(kFloorAlbedo, x, z, lx, h, lz, intensity, falloff);
}

const std::string kPoint = R"({"type": "point", "position": [0.3, 1, 0.2], "intensity": 2})";
double pointReference() {
  return meanOverSquare([](double x, double z) { return pointRadiance(x, z, 0.3, 1, 0.2, 2); });
}

// Straight down from (0, 1, 0), full intensity within 15 degrees, none beyond 30, the
// square of a linear ramp in the cosine between (KHR_lights_punctual's suggestion). The
// outer cone meets the floor at radius tan 30 = 0.58, inside the square seen (0.73).
const std::string kSpot =
    R"({"type": "spot", "position": [0, 1, 0], "direction": [0, -1, 0], "intensity": 3,
        "inner_cone": 15, "outer_cone": 30})";
double spotReference() {
  const double cosInner = std::cos(15 * kFloorPi / 180), cosOuter = std::cos(30 * kFloorPi / 180);
  return meanOverSquare([&](double x, double z) {
    const double cosAngle = 1 / std::sqrt(x * x + z * z + 1);
    const double t = std::clamp((cosAngle - cosOuter) / (cosInner - cosOuter), 0.0, 1.0);
    return pointRadiance(x, z, 0, 1, 0, 3, t * t);
  });
}

// Irradiance 2 from a direction 30 degrees off the vertical: albedo / pi * 2 * cos 30.
const std::string kDirectional = R"({"type": "directional", "direction": [0.5, -0.8660254, 0], "intensity": 2})";
double directionalReference() { return kFloorAlbedo / kFloorPi * 2 * std::cos(30 * kFloorPi / 180); }

struct Case {
  const char* name;
  std::string light;
  double reference;
};

std::vector<Case> cases() {
  return {{"point", kPoint, pointReference()}, {"spot", kSpot, spotReference()},
          {"directional", kDirectional, directionalReference()}};
}

RenderSettings floorSettings(int spp) {
  RenderSettings s;
  s.width = s.height = 16;
  s.spp = spp;
  s.maxDepth = 3;
  s.tileSize = 8;
  return s;
}

// The frame mean over seeds, with its standard error from their spread: bdpt's light
// tracing splats into other pixels, so per-pixel variances do not bound its error.
test_support::MeanEstimate meanOverSeeds(Scene scene, const std::function<FrameImage(const Scene&)>& render) {
  const int seeds = 8;
  double sum = 0, squares = 0;
  for (int seed = 0; seed < seeds; ++seed) {
    scene.seed = static_cast<uint64_t>(seed);
    const FrameImage image = render(scene);
    const auto& g = image.channel("G");
    double frame = 0;
    for (const float v : g) frame += v;
    frame /= static_cast<double>(g.size());
    sum += frame;
    squares += frame * frame;
  }
  const double mean = sum / seeds;
  return {mean, std::sqrt(std::max(0.0, squares / seeds - mean * mean) / (seeds - 1))};
}

TEST(PunctualRender, PathTracerBdptAndGradientMatchTheClosedForm) {
  const RenderSettings s = floorSettings(8);
  const std::vector<std::pair<const char*, std::function<FrameImage(const Scene&)>>> integrators = {
      {"pt", [&](const Scene& scene) { return FrameRenderer(scene, s).render(0); }},
      {"bdpt", [&](const Scene& scene) { return BdptFrameRenderer(scene, s).render(0); }},
      {"gpt", [&](const Scene& scene) { return GradientFrameRenderer(scene, s, {}).render(0); }}};
  for (const Case& c : cases()) {
    EXPECT_GT(c.reference, 0.05);
    for (const auto& [integrator, render] : integrators) {
      const auto estimate = meanOverSeeds(floorLitBy(c.light), render);
      EXPECT_NEAR(estimate.mean, c.reference, 4 * estimate.standardError + 1e-6)
          << c.name << " light, " << integrator << ", reference " << c.reference;
    }
  }
}

// The point light hangs inside the camera's view, 1 below it. It has no area, so no
// pixel shows it: light tracing (bdpt's t = 1) must not splat a dot where it projects.
// The brightest floor radiance is albedo / pi * 2 = 0.32, right below the light.
TEST(PunctualRender, APointLightInViewIsNotSeen) {
  const FrameImage image = BdptFrameRenderer(floorLitBy(kPoint), floorSettings(16)).render(0);
  for (const float v : image.channel("G")) EXPECT_LT(v, 0.6f);
}

TEST(PunctualRender, MetropolisMethodsMatchTheClosedForm) {
  for (const Case& c : cases()) {
    for (const MetropolisMethod method :
         {MetropolisMethod::Pssmlt, MetropolisMethod::PathSpace, MetropolisMethod::Temporal}) {
      const MetropolisSettings s = test_support::smallMetropolisSettings(method, 16);
      const auto estimate = meanOverSeeds(
          floorLitBy(c.light), [&](const Scene& scene) { return MetropolisRenderer(scene, s).render({0, 1})[0]; });
      EXPECT_NEAR(estimate.mean, c.reference, 4 * estimate.standardError + 1e-6)
          << c.name << " light, " << nameOf(method) << ", reference " << c.reference;
    }
  }
}

TEST(PunctualRender, ThreadsAndTileSizesGiveIdenticalBits) {
  const Scene scene = floorLitBy(kSpot);
  const auto pt = test_support::renderedTwoWays(
      floorSettings(2), [&](const RenderSettings& s) { return FrameRenderer(scene, s).render(0); });
  const auto bdpt = test_support::renderedTwoWays(
      floorSettings(2), [&](const RenderSettings& s) { return BdptFrameRenderer(scene, s).render(0); });
  for (const auto* pair : {&pt, &bdpt})
    for (const std::string& name : pair->first.channelNames())
      EXPECT_EQ(pair->first.channel(name), pair->second.channel(name)) << name;
}

}  // namespace
}  // namespace pathfarm
