// The temporal correspondence of a moving sphere in front of a still wall: where the
// sphere goes, one-to-one, nothing where the forward-backward check fails.
#include "renderer/gradient/temporal_correspondence.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "renderer/accel/shot_geometry.h"
#include "test_support.h"

namespace pathfarm {
namespace {

// A sphere moving 0.2 units right per frame (24 fps) in front of a wall.
const char* const kMovingSphere = R"({
  "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov": 40},
  "materials": {"white": {"type": "diffuse"}},
  "shapes": [
    {"type": "rectangle", "size": [20, 20], "material": "white", "transform": {"translate": [0, 0, -1]}},
    {"type": "sphere", "radius": 0.5, "material": "white",
     "animation": {"translate": [{"frame": 0, "value": [-1, 0, 0]}, {"frame": 10, "value": [1, 0, 0]}]}}]})";

TEST(TemporalCorrespondence, FollowsTheMotionOneToOne) {
  const Scene scene = test_support::sceneFromJson(kMovingSphere);
  const int w = 48, h = 32;
  const EmbreeDevice device;
  const ShotGeometry shot(scene, device);
  const FrameGeometry current(shot, 4), next(shot, 5);
  const Camera camera(scene.camera, w, h);
  const std::vector<int32_t> target = temporalCorrespondence(current, next, camera, w, h, true);

  std::set<int32_t> targets;
  int missing = 0;
  for (int32_t t : target) {
    if (t < 0) {
      ++missing;
      continue;
    }
    EXPECT_TRUE(targets.insert(t).second) << "target " << t << " claimed twice";
  }
  // Pixels behind the sphere's leading edge are covered in the next frame.
  EXPECT_GT(missing, 0);
  EXPECT_LT(missing, w * h / 10);

  // The wall far from the sphere stays; the sphere's centre moves with its projection.
  EXPECT_EQ(target[2 * w + 2], 2 * w + 2);
  const auto centreAt = [&](int64_t frame) {
    return *camera.project(Vec3f{-1 + 0.2f * frame, 0, 0}, scene.timeAt(frame, 0));
  };
  const Vec2f from = centreAt(4), to = centreAt(5);
  const int px = static_cast<int>(from.x), py = static_cast<int>(from.y);
  const int32_t moved = target[static_cast<size_t>(py * w + px)];
  ASSERT_GE(moved, 0);
  EXPECT_NEAR(moved % w, px + (to.x - from.x), 1.0);
  EXPECT_NEAR(moved / w, py, 1.0);
  EXPECT_GT(to.x - from.x, 2.0f);  // the test moves by whole pixels

  const std::vector<int32_t> still = temporalCorrespondence(current, next, camera, w, h, false);
  for (size_t p = 0; p < still.size(); ++p) EXPECT_EQ(still[p], static_cast<int32_t>(p));
}

}  // namespace
}  // namespace pathfarm
