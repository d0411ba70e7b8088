// Bidirectional path tracing against the path tracer: the same images up to noise, the
// same bits for any thread count and tile size, and black (not NaN) where no light
// reaches the camera.
#include "renderer/bidirectional/bdpt_frame_renderer.h"

#include <gtest/gtest.h>

#include "test_support.h"
#include "tests/renderer/sky_furnace.h"

namespace pathfarm {
namespace {

RenderSettings smallSettings(int size, int spp) {
  RenderSettings settings;
  settings.width = settings.height = size;
  settings.spp = spp;
  settings.maxDepth = 5;
  settings.tileSize = 8;
  return settings;
}

// relMSE of the BDPT image against the path tracer's, and what it would be from their
// noise alone: the path tracer's per-pixel variance channel, and for BDPT (whose variance
// channel leaves out the light-tracing splats) half the squared difference of two renders
// with independent seeds, whose mean is compared.
void expectAgreement(const std::string& sceneFile, int size, int ptSpp, int bdptSpp) {
  Scene scene = loadScene(test_support::sourceDir() / sceneFile);
  const FrameImage pt = FrameRenderer(scene, smallSettings(size, ptSpp)).render(2);
  const FrameImage first = BdptFrameRenderer(scene, smallSettings(size, bdptSpp)).render(2);
  scene.seed += 1;
  const FrameImage second = BdptFrameRenderer(scene, smallSettings(size, bdptSpp)).render(2);
  double relMse = 0, expected = 0;
  size_t terms = 0;
  for (const char* c : {"R", "G", "B"}) {
    const auto& reference = pt.channel(c);
    const auto& ptVariance = pt.channel(std::string("variance.") + c);
    const auto& a = first.channel(c);
    const auto& b = second.channel(c);
    for (size_t i = 0; i < reference.size(); ++i) {
      ASSERT_TRUE(std::isfinite(a[i]) && std::isfinite(b[i]));
      const double mean = 0.5 * (a[i] + b[i]);
      const double denominator = double(reference[i]) * reference[i] + 0.01;
      relMse += (mean - reference[i]) * (mean - reference[i]) / denominator;
      // var(mean of two) = E[(a - b)^2] / 4.
      expected += (ptVariance[i] + 0.25 * (a[i] - b[i]) * (a[i] - b[i])) / denominator;
      ++terms;
    }
  }
  relMse /= static_cast<double>(terms);
  expected /= static_cast<double>(terms);
  // Both are means of thousands of terms; 1.5x leaves room for their fluctuation, while a
  // bias of a few percent in bright pixels would exceed it.
  EXPECT_LT(relMse, 1.5 * expected) << sceneFile;
  EXPECT_GT(expected, 0.0);
}

TEST(BdptRender, AgreesWithThePathTracerOnTheCornellBox) {
  expectAgreement("scenes/cornell/scene.json", 24, 256, 48);
}

TEST(BdptRender, AgreesWithThePathTracerOnTheMaterialsScene) {
  expectAgreement("scenes/materials/scene.json", 24, 256, 48);
}

// The sky furnace (sky_furnace.h): the environment is reached by escaping camera subpaths
// and by connections towards it only, and their MIS weights must still add up to one.
// The scene has no surface emitter, so no light-tracing splat leaves the variance
// channel short: 4 standard errors of the pixel means.
void expectSkyFurnace(test_support::SkySource sky) {
  const auto means = test_support::skyFurnaceMeans(
      BdptFrameRenderer(test_support::skyFurnaceScene(0, sky), smallSettings(24, 32)).render(0));
  EXPECT_NEAR(means.sphere.mean, test_support::kSkyFurnaceSphere, 4 * means.sphere.standardError);
  EXPECT_NEAR(means.sky.mean, test_support::kSkyFurnaceSky, 1e-6);  // seen directly: no noise
  EXPECT_GT(means.sphere.standardError, 0);
}

TEST(BdptRender, SkyFurnaceReadsAlbedoOnTheSphereAndOneOnTheSky) {
  expectSkyFurnace(test_support::SkySource::Radiance);
}
TEST(BdptRender, SkyFurnaceUnderAConstantMap) { expectSkyFurnace(test_support::SkySource::ConstantMap); }

TEST(BdptRender, ThreadsAndTileSizesGiveIdenticalBits) {
  const Scene scene = loadScene(test_support::sourceDir() / "scenes/cornell/scene.json");
  RenderSettings settings = smallSettings(20, 2);
  settings.height = 14;
  const auto [a, b] = test_support::renderedTwoWays(
      settings, [&](const RenderSettings& s) { return BdptFrameRenderer(scene, s).render(7); });
  ASSERT_EQ(a.channelNames(), b.channelNames());
  for (const std::string& name : a.channelNames()) EXPECT_EQ(a.channel(name), b.channel(name)) << name;
}

TEST(BdptRender, LightThatCannotReachTheCameraGivesABlackImage) {
  // A lamp sealed in a box that the camera sees from outside.
  const Scene scene = test_support::sceneFromJson(R"({
    "render": {"resolution": [16, 16], "spp": 4, "max_depth": 4},
    "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov": 40},
    "materials": {"white": {"type": "diffuse", "reflectance": 0.8}},
    "shapes": [{"name": "lamp", "type": "sphere", "radius": 0.2, "material": "white", "emission": [5, 5, 5]},
               {"name": "crate", "type": "box", "size": [1, 1, 1], "material": "white"}]
  })");
  const FrameImage image = BdptFrameRenderer(scene, smallSettings(16, 4)).render(0);
  // Black up to connections grazing the crate's edges, where ray offsets can step
  // through a corner (values around 1e-15).
  for (const std::string& name : image.channelNames())
    for (const float v : image.channel(name)) ASSERT_TRUE(std::isfinite(v) && std::abs(v) < 1e-9f) << name << " " << v;
}

}  // namespace
}  // namespace pathfarm
