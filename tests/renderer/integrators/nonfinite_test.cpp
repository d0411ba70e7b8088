// A sample that comes out NaN or infinite is dropped and counted, never written.
#include <gtest/gtest.h>

#include <limits>

#include "renderer/integrators/frame_renderer.h"
#include "test_support.h"

namespace pathfarm {
namespace {

TEST(NonFiniteSamples, AreDroppedCountedAndNeverWritten) {
  // The loader refuses such values; a scene built in code can still carry them.
  Scene scene = test_support::sceneFromJson(R"({
    "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "fov": 60},
    "materials": {"m": {"type": "diffuse", "reflectance": 0.5}},
    "environment": {"radiance": 1},
    "shapes": [{"type": "sphere", "radius": 0.5, "material": "m", "emission": 1}]
  })");
  scene.objects[0].emission = Rgb(std::numeric_limits<float>::quiet_NaN());
  RenderSettings settings;
  settings.width = settings.height = 16;
  settings.spp = 8;
  RenderStats stats;
  const FrameImage image = FrameRenderer(scene, settings).render(0, {}, &stats);

  EXPECT_GT(stats.nonFiniteSamples, 0u);
  EXPECT_LT(stats.nonFiniteSamples, stats.samples);  // the background stays finite
  EXPECT_EQ(image.attributes().at("pathfarm.nonfinite_samples"), std::to_string(stats.nonFiniteSamples));
  for (const std::string& name : image.channelNames()) {
    for (const float v : image.channel(name)) ASSERT_TRUE(std::isfinite(v)) << name;
  }
  // Corner pixels see only the environment: exactly 1.
  EXPECT_EQ(image.channel("G")[0], 1.0f);
}

}  // namespace
}  // namespace pathfarm
