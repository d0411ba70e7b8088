// Keyframed objects and cameras are where interpolation says, and the traced scene
// agrees with the animation at any time inside a frame's shutter.
#include <gtest/gtest.h>

#include "renderer/accel/frame_geometry.h"
#include "renderer/math/animation.h"
#include "test_support.h"

namespace pathfarm {
namespace {

using test_support::expectNear;

TEST(Animation, TracksInterpolateAndHoldOutsideTheirKeys) {
  AnimatedTrs animation(Trs{{9, 9, 9}, {}, {1, 1, 1}});
  animation.setTranslationKeys({{0.0, {0, 0, 0}}, {1.0, {2, 0, 0}}, {3.0, {2, 4, 0}}});
  animation.setRotationKeys({{0.0, Quaternion::fromAxisAngle({0, 1, 0}, 0)},
                             {2.0, Quaternion::fromAxisAngle({0, 1, 0}, kPi / 2)}});
  animation.setScaleKeys({{0.0, {1, 1, 1}}, {2.0, {3, 1, 2}}});

  expectNear(animation.at(-1).translation, {0, 0, 0});
  expectNear(animation.at(0.25).translation, {0.5f, 0, 0});
  expectNear(animation.at(2.0).translation, {2, 2, 0});
  expectNear(animation.at(5.0).translation, {2, 4, 0});
  // Halfway through a 90 degree turn about y: 45 degrees, x goes towards -z.
  const float h = std::sqrt(0.5f);
  expectNear(animation.at(1.0).rotation.rotate({1, 0, 0}), {h, 0, -h});
  expectNear(animation.at(1.0).scale, {2, 1, 1.5f});
  // The composed transform applies scale, then rotation, then translation.
  expectNear(animation.transformAt(1.0).point({1, 0, 0}), Vec3f{2 * h, 0, -2 * h} + Vec3f{2, 0, 0});
  EXPECT_TRUE(animation.isAnimated());
  EXPECT_TRUE(animation.hasKeyInside(0.5, 1.5));
  EXPECT_FALSE(animation.hasKeyInside(1.0, 2.0));
}

TEST(Animation, SlerpTakesTheShorterArcAtConstantSpeed) {
  const Quaternion a = Quaternion::fromAxisAngle({0, 0, 1}, 0.1f);
  const Quaternion b = Quaternion::fromAxisAngle({0, 0, 1}, 2.5f);
  for (const float t : {0.0f, 0.3f, 0.7f, 1.0f}) {
    const Vec3f v = slerp(a, b, t).rotate({1, 0, 0});
    const float angle = 0.1f + t * 2.4f;
    expectNear(v, {std::cos(angle), std::sin(angle), 0});
  }
  // -b is the same rotation; slerp must not take the long way round.
  const Quaternion minusB{-b.w, -b.x, -b.y, -b.z};
  expectNear(slerp(a, minusB, 0.5f).rotate({1, 0, 0}), {std::cos(1.3f), std::sin(1.3f), 0});
}

// A sphere of radius 0.1 moving along x from -1 (frame 0) to +1 (frame 10) at 10 fps,
// seen by a camera that itself slides along x from 0 to 1 over the same time.
const char* kMovingScene = R"({
  "fps": 10,
  "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov": 30, "shutter": [0, 1],
             "animation": {"translate": [{"frame": 0, "value": [0, 0, 5]}, {"frame": 10, "value": [1, 0, 5]}],
                           "rotate": [{"frame": 0, "axis": [0, 1, 0], "angle": 0},
                                      {"frame": 10, "axis": [0, 1, 0], "angle": 90}]}},
  "materials": {"m": {"type": "diffuse"}},
  "shapes": [{"type": "sphere", "radius": 0.1, "material": "m", "object_id": 42,
              "animation": {"translate": [{"time": 0, "value": [-1, 0, 0]}, {"time": 1, "value": [1, 0, 0]}]}},
             {"type": "box", "size": [0.2, 0.2, 0.2], "material": "m", "transform": {"translate": [0, 3, 0]},
              "animation": {"rotate": [{"frame": 0, "axis": [0, 1, 0], "angle": 0},
                                       {"frame": 10, "axis": [0, 1, 0], "angle": 90}]}}]
})";

TEST(Animation, TracedSphereIsWhereTheKeysSayInsideTheShutter) {
  const Scene scene = test_support::sceneFromJson(kMovingScene);
  EmbreeDevice device;
  const ShotGeometry shot(scene, device);
  const FrameGeometry frame4(shot, 4);
  for (const float shutter : {0.0f, 0.25f, 0.5f, 1.0f}) {
    // Frame 4 spans t = 0.4 s .. 0.5 s; the sphere's center is at x = -1 + 2t.
    const float x = -1.0f + 2.0f * static_cast<float>(scene.timeAt(4, shutter));
    SurfaceHit hit;
    ASSERT_TRUE(frame4.intersect({{x, 0, 5}, {0, 0, -1}}, shutter, hit)) << shutter;
    EXPECT_EQ(scene.objects[static_cast<size_t>(hit.object)].objectId, 42u);
    EXPECT_NEAR(hit.distance, 4.9f, 1e-4f);
    expectNear(hit.geometricNormal, {0, 0, 1}, 1e-4f);
    // Just beside the sphere at that time there is nothing.
    EXPECT_FALSE(frame4.intersect({{x + 0.11f, 0, 5}, {0, 0, -1}}, shutter, hit));
  }
}

TEST(Animation, TracedBoxTurnsWithItsRotationKeys) {
  const Scene scene = test_support::sceneFromJson(kMovingScene);
  EmbreeDevice device;
  const ShotGeometry shot(scene, device);
  const FrameGeometry frame(shot, 5);  // t = 0.5 s at shutter 0: turned 45 degrees
  SurfaceHit hit;
  ASSERT_TRUE(frame.intersect({{0.02f, 3, 5}, {0, 0, -1}}, 0, hit));
  // A cube turned 45 degrees about y shows an edge to +z; just right of it lies the
  // former +z face, now facing (1, 0, 1) / sqrt(2), at distance 0.1 from the center.
  const float h = std::sqrt(0.5f);
  expectNear(hit.geometricNormal, {h, 0, h}, 1e-4f);
  EXPECT_NEAR(hit.distance, 5.0f - (0.1f / h - 0.02f), 1e-4f);
}

TEST(Animation, CameraFollowsItsKeys) {
  const Scene scene = test_support::sceneFromJson(kMovingScene);
  const Camera camera(scene.camera, 101, 101);
  // At t = 0.5 s the camera is at x = 0.5 and has turned 45 degrees about y: looking
  // along -z rotated by 45 degrees, i.e. towards (-1, 0, -1).
  const Ray ray = camera.generateRay({50.5f, 50.5f}, {0.5f, 0.5f}, 0.5);
  expectNear(ray.origin, {0.5f, 0, 5});
  const float h = std::sqrt(0.5f);
  expectNear(ray.direction, {-h, 0, -h});
}

TEST(Animation, AZoomedCameraSeesItsWindowOfThePictureAtTheSamePixelSize) {
  // Zoomed in 4x, a 16x12 frame is a window of the 64x48 one: about the picture's centre,
  // its pixel (x, y) is the full frame's (x + 24, y + 18); about the point a quarter across
  // and three quarters down, (x + 8, y + 30). The same ray at any time of the camera's
  // motion, and points (and directions) project back to the same window pixel.
  const Scene scene = test_support::sceneFromJson(kMovingScene);
  const Camera full(scene.camera, 64, 48);
  struct Window {
    CameraDesc desc;
    Vec2f corner;
  };
  for (const Window& window : {Window{zoomedIn(scene.camera, 4.0), {24, 18}},
                               Window{zoomedIn(scene.camera, 4.0, 0.25, 0.75), {8, 30}}}) {
    const Camera part(window.desc, 16, 12);
    for (const double seconds : {0.0, 0.3, 0.5})
      for (const Vec2f film : {Vec2f{0.5f, 0.5f}, Vec2f{15.25f, 3.75f}, Vec2f{8.0f, 11.9f}}) {
        const Ray a = part.generateRay(film, {0.5f, 0.5f}, seconds);
        const Ray b = full.generateRay({film.x + window.corner.x, film.y + window.corner.y}, {0.5f, 0.5f}, seconds);
        expectNear(a.origin, b.origin);
        expectNear(a.direction, b.direction, 1e-5f);
        for (const std::optional<Vec2f> back : {part.project(a.origin + a.direction * 3.0f, seconds),
                                                part.projectDirection(a.direction, seconds)}) {
          ASSERT_TRUE(back.has_value());
          EXPECT_NEAR(back->x, film.x, 1e-3f);
          EXPECT_NEAR(back->y, film.y, 1e-3f);
        }
      }
  }
}

}  // namespace
}  // namespace pathfarm
