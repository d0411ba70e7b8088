// Renders under environment maps against answers found without the renderer's light
// sampling: a floor under a sky of two hemispheres reflects albedo x the upper one, and
// under a sky with a small sun it converges to the mean that BSDF sampling alone finds.
// Both for the path tracer and BDPT (and gradient-domain differences that vanish where
// they must), with the same bits for any threads and tiles.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "renderer/bidirectional/bdpt_frame_renderer.h"
#include "renderer/integrators/gradient_frame_renderer.h"
#include "renderer/math/sampling.h"
#include "test_support.h"
#include "tests/renderer/sky_map.h"

namespace pathfarm {
namespace {

namespace fs = std::filesystem;

constexpr float kAlbedo = 0.5f;

// A diffuse floor of albedo 1/2, 200 wide, filling the view of a camera 2 above it
// looking straight down: every pixel sees the floor, and every floor point sees the whole
// upper hemisphere of the sky and nothing else.
Scene floorUnder(const fs::path& map) {
  return test_support::sceneFromJson(R"({
    "camera": {"position": [0, 2, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": 40},
    "materials": {"floor": {"type": "diffuse", "reflectance": 0.5}},
    "environment": {"map": ")" + map.string() + R"("},
    "shapes": [{"type": "rectangle", "size": [200, 200], "material": "floor",
                "transform": {"rotate": {"axis": [1, 0, 0], "angle": -90}}}]})");
}

RenderSettings settings(int spp) {
  RenderSettings s;
  s.width = s.height = 16;
  s.spp = spp;
  s.maxDepth = 4;
  s.tileSize = 8;
  return s;
}

test_support::MeanEstimate ptMean(const Scene& scene, int spp) {
  return test_support::meanOverPixels(FrameRenderer(scene, settings(spp)).render(0), "G");
}

test_support::MeanEstimate bdptMean(const Scene& scene, int spp) {
  return test_support::meanOverPixels(BdptFrameRenderer(scene, settings(spp)).render(0), "G");
}

// Upper hemisphere 1, lower 4: the floor reads albedo x 1 (a sky upside down would give
// albedo x 4). Bilinear lookups blend the two only within half a texel row of the
// horizon, pi / 1024 here, where cos(theta) weighs the blend by about (pi / 1024)^2 / 2:
// far below the standard error.
fs::path hemisphereSky() {
  const fs::path file = test_support::skyMapFolder() / "hemisphere_1_4.hdr";
  test_support::writeSkyMap(file, 32, 512, test_support::hemisphereSkyTexels(32, 512, Rgb(1), Rgb(4)));
  return file;
}

TEST(EnvironmentRender, FloorUnderAHemisphereSkyReflectsAlbedoTimesTheUpperHalf) {
  const Scene scene = floorUnder(hemisphereSky());
  for (const auto& [name, estimate] : {std::pair{"pt", ptMean(scene, 16)}, std::pair{"bdpt", bdptMean(scene, 16)}}) {
    EXPECT_NEAR(estimate.mean, kAlbedo * 1.0, 4 * estimate.standardError) << name;
    EXPECT_GT(estimate.standardError, 0) << name;
  }
}

// Gradient-domain path tracing under the same sky: base and offset paths from any two
// floor points see the same sky, so the finite differences vanish, and the primal reads
// albedo x the upper half.
TEST(EnvironmentRender, GradientDifferencesVanishOnAFloorUnderAHemisphereSky) {
  const FrameImage image = GradientFrameRenderer(floorUnder(hemisphereSky()), settings(8), {}).render(0);
  for (const char* c : {"R", "G", "B"}) {
    for (const std::string layer : {"gradient_x.", "gradient_y."})
      for (const float g : image.channel(layer + c)) ASSERT_NEAR(g, 0.0f, 1e-5f) << layer << c;
    const auto mean = test_support::meanOverPixels(image, c);
    EXPECT_NEAR(mean.mean, kAlbedo * 1.0, 4 * mean.standardError + 1e-6) << c;
  }
}

// A dim sky (0.3) with a sun of radiance 200 and 3.6 degrees' radius at 62 degrees'
// elevation: about 2.2 of the floor's irradiance comes from the sun, 0.9 from the sky.
const Vec3f kSun = normalize(Vec3f{0.5f, 1.2f, -0.4f});
fs::path sunSky() {
  const fs::path file = test_support::skyMapFolder() / "sun.hdr";
  test_support::writeSkyMap(file, 256, 128, test_support::skyMapTexels(256, 128, [](Vec3f d) {
                              return dot(d, kSun) > 0.998f ? Rgb(200) : Rgb(0.3f);
                            }));
  return file;
}

// The floor's radiance by BSDF sampling alone, outside the renderer: cosine-weighted
// directions around +y, each worth albedo x L(direction) (the cosine and 1/pi cancel).
test_support::MeanEstimate bsdfSamplingOnly(const EnvironmentLight& sky, int n) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> uniform(0, 1);
  double sum = 0, squares = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3f local = sampleCosineHemisphere({uniform(rng), uniform(rng)});
    const double x = kAlbedo * sky.radiance({local.x, local.z, local.y}).g;
    sum += x;
    squares += x * x;
  }
  const double mean = sum / n;
  return {mean, std::sqrt((squares / n - mean * mean) / (n - 1))};
}

TEST(EnvironmentRender, SunSkyConvergesToTheBsdfSampledMean) {
  const Scene scene = floorUnder(sunSky());
  const auto reference = bsdfSamplingOnly(scene.environment, 16'000'000);
  for (const auto& [name, estimate] : {std::pair{"pt", ptMean(scene, 128)}, std::pair{"bdpt", bdptMean(scene, 128)}}) {
    const double sigma = std::hypot(estimate.standardError, reference.standardError);
    EXPECT_NEAR(estimate.mean, reference.mean, 4 * sigma) << name << " against " << reference.mean;
    // Next-event estimation finds the sun. Per sample, BSDF sampling's variance is about
    // (albedo 200)^2 x the chance 0.0126 cos / pi of hitting the sun, some 35, while
    // sampling the map makes L / pdf nearly constant: a variance of the order of the
    // mean squared (0.25). A factor of 20 between them leaves room on both sides.
    const double renderPerSample = estimate.standardError * estimate.standardError * 16 * 16 * 128;
    const double referencePerSample = reference.standardError * reference.standardError * 16'000'000;
    EXPECT_LT(renderPerSample, referencePerSample / 20) << name;
  }
}

TEST(EnvironmentRender, ThreadsAndTileSizesGiveIdenticalBitsUnderAMap) {
  const Scene scene = floorUnder(sunSky());
  const auto pt = test_support::renderedTwoWays(
      settings(2), [&](const RenderSettings& s) { return FrameRenderer(scene, s).render(0); });
  const auto bdpt = test_support::renderedTwoWays(
      settings(2), [&](const RenderSettings& s) { return BdptFrameRenderer(scene, s).render(0); });
  for (const auto* pair : {&pt, &bdpt})
    for (const std::string& name : pair->first.channelNames())
      EXPECT_EQ(pair->first.channel(name), pair->second.channel(name)) << name;
}

}  // namespace
}  // namespace pathfarm
