#include "renderer/integrators/shutter_buckets.h"

#include <gtest/gtest.h>

#include <cmath>

#include "renderer/scene/scene_loader.h"
#include "test_support.h"

namespace pathfarm {
namespace {

// Every shutter fraction lands on the centre of the bucket that holds it (the ends clamped),
// and its placement is the camera's own at that centre: the dolly's camera moves and turns.
TEST(ShutterBuckets, ASampleTakesItsBucketsCentreAndTheCamerasPlacementThere) {
  const Scene scene = loadScene(test_support::sourceDir() / "scenes/dolly/scene.json");
  const Camera camera(scene.camera, 64, 36);
  ASSERT_TRUE(scene.camera.transform.isAnimated());
  ASSERT_GT(scene.camera.shutterClose, scene.camera.shutterOpen);
  constexpr int64_t kFrame = 7;
  const ShutterBuckets shutter(scene, camera, kFrame);
  const float halfBucket = 0.5f / ShutterBuckets::kBuckets;
  for (const float u : {0.0f, 1e-6f, 0.25f, 0.3333f, 0.5f, 0.74f, 0.999f, 0.99999f}) {
    const float t = shutter.time(u);
    EXPECT_LE(std::abs(t - u), halfBucket * 1.0001f) << u;
    EXPECT_EQ(shutter.time(t), t) << "a centre is its own bucket's, " << u;
    const Transform exact = camera.cameraToWorld(scene.timeAt(kFrame, t));
    const Transform& bucketed = shutter.cameraToWorld(u);
    for (const Vec3f p : {Vec3f{0, 0, 0}, Vec3f{1, -2, 3}, Vec3f{-5, 0.5f, -10}}) {
      const Vec3f a = bucketed.point(p), b = exact.point(p);
      EXPECT_EQ(a.x, b.x) << u;
      EXPECT_EQ(a.y, b.y) << u;
      EXPECT_EQ(a.z, b.z) << u;
    }
  }
  EXPECT_EQ(shutter.time(-0.5f), halfBucket);
  EXPECT_EQ(shutter.time(1.0f), 1.0f - halfBucket);
  // Neighbouring buckets hold different placements: the table follows the animation.
  const Vec3f first = shutter.cameraToWorld(0.0f).point({0, 0, 0});
  const Vec3f last = shutter.cameraToWorld(0.9999f).point({0, 0, 0});
  EXPECT_NE(first.z, last.z);
}

}  // namespace
}  // namespace pathfarm
