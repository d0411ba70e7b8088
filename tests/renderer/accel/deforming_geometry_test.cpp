// Deforming meshes in the renderer: rays meet the skinned arm of gltf_arm.h where its
// joints have turned at the ray's time (following the arc across the shutter, not a
// line between its ends), surface points are followed through time by their triangle,
// motion vectors follow the turning joint, and a frame of the skinned arm renders as the
// same pose written out by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "renderer/accel/frame_geometry.h"
#include "renderer/decomposition/primary_motion.h"
#include "renderer/integrators/frame_renderer.h"
#include "renderer/scene/scene_loader.h"
#include "test_support.h"
#include "tests/renderer/scene/gltf/gltf_arm.h"

namespace pathfarm {
namespace {

using test_support::expectNear;

std::filesystem::path armFolder() { return test_support::processTemporaryFolder("pathfarm_deforming"); }

// The forearm's point at (x, y) from the elbow, with the elbow turned by `radians` about z.
Vec3f forearmPoint(float x, float y, double radians) {
  const float c = static_cast<float>(std::cos(radians)), s = static_cast<float>(std::sin(radians));
  return {1 + x * c - y * s, x * s + y * c, 0};
}

// The arm turning about z, with frame 0's shutter spanning the whole turn (one second).
Scene armTurningThroughFrameZero() {
  gltftest::GltfBuilder b = gltftest::skinnedArm({0, 0, 1});
  Scene scene = loadScene(b.write(armFolder(), "arm_shutter"));
  scene.fps = 1;
  scene.camera.shutterOpen = 0;
  scene.camera.shutterClose = 1;
  return scene;
}

// Where a ray straight down onto the plane z = 0 through (p.x, p.y) meets the scene at `time`.
std::optional<SurfaceHit> downOnto(const FrameGeometry& frame, Vec3f p, float time) {
  SurfaceHit hit;
  if (!frame.intersect({{p.x, p.y, 5}, {0, 0, -1}}, time, hit)) return std::nullopt;
  return hit;
}

TEST(DeformingGeometry, ARayMeetsTheArmWhereItsJointHasTurnedAtTheRaysTime) {
  const Scene scene = armTurningThroughFrameZero();
  ASSERT_TRUE(scene.objects[0].deformation);
  const EmbreeDevice device;
  const ShotGeometry shot(scene, device);
  EXPECT_TRUE(shot.shape(0).deforming);
  const FrameGeometry frame(shot, 0);
  // Mid-shutter is one of the posed steps: exact.
  const Vec3f midway = forearmPoint(0.9f, 0.5f, 0.25 * kPi);
  const auto hit = downOnto(frame, midway, 0.5f);
  ASSERT_TRUE(hit);
  expectNear(hit->position, midway, 1e-4f);
  expectNear(hit->shadingNormal, {0, 0, 1}, 1e-5f);
  // Followed by its triangle, the same point of the forearm at the turn's ends.
  expectNear(shot.surfacePointAt(*hit, 0.0), forearmPoint(0.9f, 0.5f, 0), 1e-5f);
  expectNear(shot.surfacePointAt(*hit, 1.0), forearmPoint(0.9f, 0.5f, 0.5 * kPi), 1e-5f);
  // Between steps the forearm lies on the chord of a 22.5-degree arc: within 2 % of its
  // reach of the arc. A line between the shutter's ends would be 0.29 off at the hand.
  const double angle = 0.375 * 0.5 * kPi;
  const Vec3f between = forearmPoint(0.9f, 0.5f, angle);
  const auto near = downOnto(frame, between, 0.375f);
  ASSERT_TRUE(near);
  EXPECT_LT(length(shot.surfacePointAt(*near, 0.375) - between), 0.02f * std::sqrt(0.9f * 0.9f + 0.25f));
  // The deformed triangle's point at that time is the hit itself.
  expectNear(frame.deformedSurface(near->object, near->primitive, near->barycentric, 0.375f).position,
             near->position, 1e-5f);
}

TEST(DeformingGeometry, MotionVectorsFollowAPointOfTheForearmAsItsJointTurns) {
  gltftest::GltfBuilder b = gltftest::skinnedArm({0, 0, 1});
  Scene scene = loadScene(b.write(armFolder(), "arm_motion"));
  scene.fps = 4;  // frame 2 is half a second in; frames 1 and 3 a quarter before and after
  const EmbreeDevice device;
  const ShotGeometry shot(scene, device);
  const FrameGeometry frame(shot, 2);
  const Camera camera(scene.camera, 64, 64);
  const auto hit = downOnto(frame, forearmPoint(0.9f, 0.5f, 0.25 * kPi), 0);
  ASSERT_TRUE(hit);
  const MotionPair motion = PrimaryMotion(frame, camera, 2).ofSurface(*hit, 0);
  const auto imageAt = [&](double quarters) {
    return *camera.project(forearmPoint(0.9f, 0.5f, quarters * 0.125 * kPi), 0);  // the camera stands still
  };
  ASSERT_TRUE(motion.forward && motion.backward);
  EXPECT_NEAR(motion.forward->x, imageAt(3).x - imageAt(2).x, 1e-3f);
  EXPECT_NEAR(motion.forward->y, imageAt(3).y - imageAt(2).y, 1e-3f);
  EXPECT_NEAR(motion.backward->x, imageAt(1).x - imageAt(2).x, 1e-3f);
  EXPECT_NEAR(motion.backward->y, imageAt(1).y - imageAt(2).y, 1e-3f);
  EXPECT_GT(std::abs(motion.forward->x) + std::abs(motion.forward->y), 1.0f);  // it does move
}

// The arm turned 45 degrees about y, written as a static mesh by hand: the forearm
// tilts down into -z, the elbow's blended vertices (3 : 1) stay in place.
std::filesystem::path armPosedByHand() {
  const float c = std::cos(0.25f * kPi), s = std::sin(0.25f * kPi);
  const float blend = std::sqrt(0.75f * s * 0.75f * s + (0.75f * c + 0.25f) * (0.75f * c + 0.25f));
  const Vec3f elbowNormal{0.75f * s / blend, 0, (0.75f * c + 0.25f) / blend};
  gltftest::GltfBuilder b;
  const int position = b.floats({0, 0, 0, 1, 0, 0, 1 + c, 0, -s, 1 + c, 1, -s, 1, 1, 0, 0, 1, 0}, "VEC3", true);
  const int normal = b.floats({0, 0, 1, elbowNormal.x, 0, elbowNormal.z, s, 0, c, s, 0, c, elbowNormal.x, 0,
                               elbowNormal.z, 0, 0, 1},
                              "VEC3");
  const int mesh = b.mesh({{"POSITION", position}, {"NORMAL", normal}},
                          b.indices(std::vector<uint16_t>{0, 1, 4, 0, 4, 5, 1, 2, 3, 1, 3, 4}));
  b.scene({b.node({{"mesh", mesh}}), b.camera({1, 0.5f, 4})});
  return b.write(armFolder(), "arm_by_hand");
}

TEST(DeformingGeometry, AFrameOfTheSkinnedArmRendersAsTheSamePoseWrittenByHand) {
  gltftest::GltfBuilder skinned = gltftest::skinnedArm({0, 1, 0});
  skinned.write(armFolder(), "arm_skinned");
  armPosedByHand();
  // Half a second in at 24 frames per second: frame 12, the elbow turned 45 degrees.
  const auto render = [](const std::string& file) {
    const Scene scene = parseScene(R"({"include": ")" + file + R"(", "environment": {"radiance": 1}})",
                                   armFolder() / (file + ".json"));
    RenderSettings settings = RenderSettings::defaultsOf(scene);
    settings.width = settings.height = 48;
    settings.spp = 4;
    return FrameRenderer(scene, settings).render(12);
  };
  const FrameImage deformed = render("arm_skinned.gltf"), byHand = render("arm_by_hand.gltf");
  const auto& a = deformed.channel("G");
  const auto& b = byHand.channel("G");
  double difference = 0, sum = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    difference += std::abs(a[i] - b[i]);
    sum += b[i];
  }
  // Same rays, same surfaces: only rounding of the vertices (and a sample at an edge) differs.
  EXPECT_GT(sum, 0.1 * static_cast<double>(a.size()));
  EXPECT_LT(difference, 2e-3 * sum);
}

}  // namespace
}  // namespace pathfarm
