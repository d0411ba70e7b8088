// Deforming meshes in the renderer: rays meet the skinned arm of gltf_arm.h where its
// joints have turned at the ray's time (following the arc across the shutter, not a
// line between its ends), surface points are followed through time by their triangle,
// motion vectors follow the turning joint, and a frame of the skinned arm renders as the
// same pose written out by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "renderer/accel/frame_geometry.h"
#include "renderer/accel/shutter_poses.h"
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
  // Between instants the forearm lies on the chord of an arc of at most 22.5 degrees:
  // within 2 % of its reach of the arc. A line between the shutter's ends would be 0.29
  // off at the hand.
  const double angle = 0.375 * 0.5 * kPi;
  const Vec3f between = forearmPoint(0.9f, 0.5f, angle);
  const auto near = downOnto(frame, between, 0.375f);
  ASSERT_TRUE(near);
  EXPECT_LT(length(shot.surfacePointAt(*near, 0.375) - between), 0.02f * std::sqrt(0.9f * 0.9f + 0.25f));
  // The deformed triangle's point at that time is the hit itself.
  expectNear(frame.deformedSurface(near->object, near->primitive, near->barycentric, 0.375f).position,
             near->position, 1e-5f);
}

TEST(DeformingGeometry, TheShutterIsPosedAtAsFewInstantsAsKeepTheBlurOnTheArc) {
  const Scene scene = armTurningThroughFrameZero();
  const MeshDeformation& arm = *scene.objects[0].deformation;
  EXPECT_EQ(shutterPoses(arm, 0.5, 0.5).size(), 1u);  // closed
  // A quarter turn in one shutter: the hand's chord strays 0.41 from its arc, 190 times the
  // tolerance of 0.0022 (the arm's extent is 2.2): four segments would leave 12 times it.
  EXPECT_EQ(shutterPoses(arm, 0, 1).size(), 9u);
  // A fiftieth of that turn strays by 1 / 2500 as much: one segment is within tolerance.
  EXPECT_EQ(shutterPoses(arm, 0.5, 0.52).size(), 2u);
  // Each pose is the deformation at its instant.
  const auto poses = shutterPoses(arm, 0, 1);
  for (size_t s = 0; s < poses.size(); ++s)
    expectNear(poses[s].positions[2], arm.positionAt(2, static_cast<double>(s) / 8), 1e-6f);
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

// A black square before a sky of radiance 1 grows by a morph target from half-size 1 to 2
// over frame 0's open shutter (one second, its weight LINEAR from 0 to 1). A point of the
// plane at max(|x|, |y|) = m is covered while 1 + t > m, for a share clamp(2 - m, 0, 1)
// of the shutter, so the blurred image there reads 1 minus that.
TEST(DeformingGeometry, MotionBlurOfAGrowingSquareIsItsTimeAveragedCoverage) {
  gltftest::GltfBuilder b;
  const int square = b.square(0);
  b.doc()["materials"] = {{{"name", "black"}}};
  b.doc()["meshes"][static_cast<size_t>(square)]["primitives"][0]["targets"] = {
      {{"POSITION", b.doc()["meshes"][static_cast<size_t>(square)]["primitives"][0]["attributes"]["POSITION"]}}};
  const int node = b.node({{"mesh", square}});
  const int times = b.floats({0, 1}, "SCALAR"), weights = b.floats({0, 1}, "SCALAR");
  b.doc()["animations"] = {{{"samplers", {{{"input", times}, {"output", weights}}}},
                            {"channels", {{{"sampler", 0}, {"target", {{"node", node}, {"path", "weights"}}}}}}}};
  b.scene({node, b.camera({0, 0, 4}, 2 * std::atan(0.75))});  // the plane z = 0 seen over [-3, 3]^2
  b.write(armFolder(), "growing");
  const Scene scene = parseScene(R"({"include": {"file": "growing.gltf", "shutter": [0, 1]}, "fps": 1,
    "materials": {"black": {"type": "diffuse", "reflectance": 0}}, "environment": {"radiance": 1}})",
                                 armFolder() / "growing.json");
  RenderSettings settings = RenderSettings::defaultsOf(scene);
  const int size = 48;
  settings.width = settings.height = size;
  settings.spp = 16;
  const FrameImage image = FrameRenderer(scene, settings).render(0);
  // Per pixel, the expected value over its area (16 x 16 points) and which half of the
  // growth band its centre lies in.
  struct Band {
    double measured = 0, expected = 0;
    int pixels = 0;
  } inner, outer;
  const auto planeAt = [&](double pixel) { return pixel / size * 6 - 3; };
  for (int py = 0; py < size; ++py)
    for (int px = 0; px < size; ++px) {
      const double m = std::max(std::abs(planeAt(px + 0.5)), std::abs(planeAt(py + 0.5)));
      if (m < 1.1 || m > 1.9) continue;
      double expected = 0;
      for (int sy = 0; sy < 16; ++sy)
        for (int sx = 0; sx < 16; ++sx) {
          const double at = std::max(std::abs(planeAt(px + (sx + 0.5) / 16)), std::abs(planeAt(py + (sy + 0.5) / 16)));
          expected += 1 - std::clamp(2 - at, 0.0, 1.0);
        }
      Band& band = m < 1.5 ? inner : outer;
      band.expected += expected / 256;
      band.measured += image.channel("G")[static_cast<size_t>(py * size + px)];
      ++band.pixels;
    }
  for (const Band* band : {&inner, &outer}) {
    ASSERT_GT(band->pixels, 100);
    // Each sample sees the sky or not: a variance of at most 1/4 per sample.
    const double sigma = std::sqrt(band->pixels * 0.25 / settings.spp);
    EXPECT_NEAR(band->measured, band->expected, 5 * sigma);
  }
  // The bands are told apart: a square frozen at mid-shutter would give 0 and 1 there.
  EXPECT_LT(inner.measured / inner.pixels, 0.45);
  EXPECT_GT(outer.measured / outer.pixels, 0.55);
}

}  // namespace
}  // namespace pathfarm
