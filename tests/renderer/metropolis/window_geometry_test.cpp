// The placed geometry of each frame of a window: the animated sphere sits where its
// keyframes put it in each frame.
#include "renderer/metropolis/window_geometry.h"

#include <gtest/gtest.h>

#include "test_support.h"

namespace pathfarm {
namespace {

TEST(WindowGeometry, EachFramePlacesTheAnimatedObjectsOfThatFrame) {
  // A unit sphere moving 1 along +x per frame; the shutter is open at the frame's start.
  const Scene scene = test_support::sceneFromJson(R"({
    "camera": {"position": [0, 0, 10], "look_at": [0, 0, 0], "shutter": [0, 0.5]},
    "materials": {"grey": {"type": "diffuse", "reflectance": 0.5}},
    "shapes": [{"type": "sphere", "radius": 1, "material": "grey",
                "animation": {"translate": [{"frame": 0, "value": [0, 0, 0]}, {"frame": 10, "value": [10, 0, 0]}]}}]
  })");
  const EmbreeDevice device;
  const ShotGeometry shot(scene, device);
  const WindowGeometry window(shot, {2, 3});
  for (int64_t f = 2; f < 5; ++f) {
    const FrameGeometry& frame = window.frame(f);
    EXPECT_EQ(frame.frame(), f);
    // A ray down -z through x = f hits the sphere's top at z = 1 at the shutter's opening.
    SurfaceHit hit;
    ASSERT_TRUE(frame.intersect({{static_cast<float>(f), 0, 5}, {0, 0, -1}}, 0, hit));
    EXPECT_NEAR(hit.position.z, 1, 1e-4);
  }
  EXPECT_THROW(window.frame(5), std::out_of_range);
  EXPECT_THROW(window.frame(1), std::out_of_range);
}

}  // namespace
}  // namespace pathfarm
