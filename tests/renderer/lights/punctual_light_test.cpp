// Punctual lights on their own and in the light sampler: the spot's power against a
// numerical integral of its falloff, emission sampling against its pdf, the sampler's
// choice in proportion to power, animated lights followed over the shutter, and JSON
// scenes that describe lights wrongly refused with the offending entry named.
#include <gtest/gtest.h>

#include <cmath>

#include "renderer/accel/frame_geometry.h"
#include "renderer/integrators/light_sampler.h"
#include "renderer/scene/scene_loader.h"
#include "test_support.h"

namespace pathfarm {
namespace {

constexpr double kPiD = 3.14159265358979323846;

PunctualLight spot(float innerDegrees, float outerDegrees) {
  PunctualLight light;
  light.type = PunctualType::Spot;
  light.intensity = Rgb(1);
  light.cosInner = std::cos(innerDegrees * static_cast<float>(kPiD) / 180);
  light.cosOuter = std::cos(outerDegrees * static_cast<float>(kPiD) / 180);
  return light;
}

// Power is intensity integrated over the sphere of directions: a midpoint sum over the
// polar angle of the spot's falloff (evaluated through intensityToward) times 2 pi sin.
TEST(PunctualLight, SpotPowerIsItsFalloffIntegratedOverTheSphere) {
  const PunctualLight light = spot(20, 50);
  const Vec3f forward{0, 0, -1};
  const int n = 200000;
  double power = 0;
  for (int i = 0; i < n; ++i) {
    const double theta = (i + 0.5) / n * kPiD;
    const Vec3f direction{static_cast<float>(std::sin(theta)), 0, -static_cast<float>(std::cos(theta))};
    power += light.intensityToward(direction, forward).g * 2 * kPiD * std::sin(theta) * (kPiD / n);
  }
  EXPECT_NEAR(light.power(1), power, 1e-4 * power);
  PunctualLight point;
  point.intensity = Rgb(1);
  EXPECT_NEAR(point.power(1), 4 * kPiD, 1e-5);
}

// Sampled directions stay inside the outer cone, and a histogram of their polar angle
// matches the uniform-cone density emissionPdf reports.
TEST(PunctualLight, SpotEmissionSamplesFollowTheirPdf) {
  const PunctualLight light = spot(10, 40);
  const Vec3f forward = normalize(Vec3f{0.3f, -1, 0.2f});
  const int bins = 8, n = 64000;
  std::vector<int> histogram(bins, 0);
  const double cosOuter = std::cos(40 * kPiD / 180);
  for (int i = 0; i < n; ++i) {
    const Vec2f u{(static_cast<float>(i % 256) + 0.5f) / 256, (static_cast<float>(i / 256) + 0.5f) / 250};
    const auto e = light.sampleEmission(u, forward);
    ASSERT_TRUE(e.has_value());
    const double c = dot(e->direction, forward);
    ASSERT_GE(c, cosOuter - 1e-5);
    EXPECT_FLOAT_EQ(e->pdf, light.emissionPdf(e->direction, forward));
    ++histogram[std::min(bins - 1, static_cast<int>((1 - c) / (1 - cosOuter) * bins))];
  }
  // Uniform over solid angle is uniform in cos theta: equal bins.
  for (const int count : histogram) EXPECT_NEAR(count, n / bins, 0.05 * n / bins);
  EXPECT_EQ(light.emissionPdf(-forward, forward), 0);
  EXPECT_NEAR(light.emissionPdf(forward, forward), 1 / (2 * kPiD * (1 - cosOuter)), 1e-4);
}

Scene sceneWithLights(const std::string& lights) {
  return test_support::sceneFromJson(R"({
    "camera": {"position": [0, 2, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "shutter": [0, 1]},
    "materials": {"m": {"type": "diffuse", "reflectance": 0.5}},
    "lights": )" + lights + R"(,
    "shapes": [{"type": "sphere", "radius": 1, "material": "m"}]})");
}

// A point light of intensity 3 (power 12 pi) and one of intensity 1 (4 pi): chosen 3 : 1.
TEST(PunctualLightSampler, ChoosesLightsInProportionToPower) {
  const Scene scene = sceneWithLights(R"([
    {"type": "point", "position": [0, 3, 0], "intensity": 3},
    {"type": "point", "position": [0, -3, 0], "intensity": 1}])");
  EmbreeDevice device;
  const ShotGeometry shot(scene, device);
  const LightSampler lights(shot);
  EXPECT_NEAR(lights.punctualProbability(0), 0.75, 1e-6);
  EXPECT_NEAR(lights.punctualProbability(1), 0.25, 1e-6);
  EXPECT_EQ(lights.choose(0.7f).index, 0);
  EXPECT_EQ(lights.choose(0.8f).index, 1);
  EXPECT_EQ(lights.choose(0.8f).kind, LightChoice::Kind::Punctual);
}

// A light moving from x = -1 to x = 1 over frame 0's open shutter: sampled at shutter
// fraction 0.25 from the origin, it lies at x = -0.5, 3 up, and gives intensity / d^2.
TEST(PunctualLightSampler, FollowsAnAnimatedLightOverTheShutter) {
  const Scene scene = sceneWithLights(R"([
    {"type": "point", "position": [0, 3, 0], "intensity": 2,
     "animation": {"translate": [{"frame": 0, "value": [-1, 3, 0]}, {"frame": 1, "value": [1, 3, 0]}]}}])");
  EmbreeDevice device;
  const ShotGeometry shot(scene, device);
  const FrameGeometry frame(shot, 0);
  const LightSampler lights(shot);
  const auto sample = lights.sample(frame, {0, 0, 0}, 0.25f, 0.5f, {0.5f, 0.5f});
  ASSERT_TRUE(sample.has_value());
  EXPECT_TRUE(sample->delta);
  const Vec3f expected{-0.5f, 3, 0};
  EXPECT_NEAR(sample->distance, length(expected), 1e-5);
  EXPECT_NEAR(dot(sample->direction, normalize(expected)), 1, 1e-6);
  EXPECT_NEAR(sample->radiance.g, 2 / dot(expected, expected), 1e-5);
  EXPECT_FLOAT_EQ(sample->pdf, 1);
}

// A directional light shines along its direction: the sample points against it, from
// infinitely far, with its irradiance.
TEST(PunctualLightSampler, DirectionalLightsComeFromInfinitelyFarAgainstTheirDirection) {
  const Scene scene = sceneWithLights(R"([{"type": "directional", "direction": [1, -1, 0], "intensity": 5}])");
  EmbreeDevice device;
  const ShotGeometry shot(scene, device);
  const FrameGeometry frame(shot, 0);
  const auto sample = LightSampler(shot).sample(frame, {0, 1, 0}, 0, 0.5f, {0.5f, 0.5f});
  ASSERT_TRUE(sample.has_value());
  EXPECT_TRUE(std::isinf(sample->distance));
  EXPECT_NEAR(dot(sample->direction, normalize(Vec3f{-1, 1, 0})), 1, 1e-6);
  EXPECT_FLOAT_EQ(sample->radiance.g, 5);
}

void expectRefused(const std::string& lights, const std::string& fragment) {
  try {
    sceneWithLights(lights);
    ADD_FAILURE() << "accepted " << lights;
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what() << " lacks " << fragment;
  }
}

TEST(PunctualLightParser, RefusesMalformedLightsNamingTheEntry) {
  expectRefused(R"([{"type": "area", "intensity": 1}])", "lights[0].type");
  expectRefused(R"([{"type": "point", "intensity": -1}])", "lights[0].intensity");
  expectRefused(R"([{"type": "point"}])", "intensity");
  expectRefused(R"([{"type": "spot", "intensity": 1, "inner_cone": 40, "outer_cone": 30}])", "lights[0].inner_cone");
  expectRefused(R"([{"type": "spot", "intensity": 1, "outer_cone": 0}])", "lights[0].outer_cone");
  expectRefused(R"([{"type": "point", "intensity": 1, "outer_cone": 30}])", "only spot lights");
  expectRefused(R"([{"type": "directional", "intensity": 1, "direction": [0, 0, 0]}])", "lights[0].direction");
  expectRefused(R"([{"type": "directional", "intensity": 1, "position": [0, 1, 0]}])", "no position");
  expectRefused(R"([{"type": "point", "intensity": 1, "position": [0, 1, 0], "transform": {}}])", "not both");
  expectRefused(R"([{"type": "point", "intensity": 1, "colour": 1}])", "colour");
}

}  // namespace
}  // namespace pathfarm
