// tmlt's temporal moves on a deforming surface: a path vertex on the skinned arm of
// gltf_arm.h keeps its triangle and barycentric point and lands where the arm's closed-form
// pose puts that point at the new time, and the area scale is the triangle's area then
// over its rest area.
#include <gtest/gtest.h>

#include <cmath>

#include "path_space_fixture.h"
#include "renderer/metropolis/path_space/vertex_motion.h"
#include "tests/renderer/scene/gltf/gltf_arm.h"

namespace pathfarm {
namespace {

// The arm's vertices at `seconds`, written out: the elbow turns a quarter about z over
// the first second, then holds.
std::array<Vec3f, 6> armAt(double seconds) {
  const double angle = 0.5 * kPi * std::clamp(seconds, 0.0, 1.0);
  const float c = static_cast<float>(std::cos(angle)), s = static_cast<float>(std::sin(angle));
  const auto turned = [&](float x, float y) { return Vec3f{1 + x * c - y * s, x * s + y * c, 0}; };
  return {Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, turned(1, 0), turned(1, 1), turned(0, 1) * 0.75f + Vec3f{1, 1, 0} * 0.25f,
          Vec3f{0, 1, 0}};
}

TEST(DeformingVertexMotion, AVertexOnTheArmKeepsItsPointOfItsTriangleAsTheArmBends) {
  const std::filesystem::path folder = test_support::processTemporaryFolder("pathfarm_deforming_tmlt");
  gltftest::GltfBuilder arm = gltftest::skinnedArm({0, 0, 1});
  const std::filesystem::path file = arm.write(folder, "arm");
  const test_support::WindowFixture f(R"({"include": {"file": ")" + file.string() +
                                          R"(", "shutter": [0, 0.5]}, "fps": 4, "environment": {"radiance": 1}})",
                                      {0, 4}, 16, 4);
  const TriangleMesh& rest = *f.shot.shape(0).mesh;
  int moved = 0;
  for (const PathSpaceState& s : f.samplePaths(300, 7)) {
    const WindowInstant here = *f.time.instant(s.tau);
    if (here.frame == 3) continue;  // the window holds frames 0 to 3
    const WindowInstant next{here.frame + 1, here.shutterFraction};
    for (const PathVertex& v : s.path.vertices) {
      if (v.type != VertexType::Surface || v.hit.object != 0) continue;
      ASSERT_TRUE(movesWithTime(f.window, v));
      const PathVertex w = placedAt(f.window, v, here, next);
      const std::array<Vec3f, 6> then = armAt(f.scene.timeAt(next.frame, next.shutterFraction));
      const std::array<Vec3f, 6> restPose = armAt(0);
      const uint32_t* corners = &rest.indices[3 * v.hit.primitive];
      const float bu = v.hit.barycentric.x, bv = v.hit.barycentric.y;
      const Vec3f expected = then[corners[0]] * (1 - bu - bv) + then[corners[1]] * bu + then[corners[2]] * bv;
      // Between the frame's five posed instants the arm is on the chord of its arc.
      EXPECT_LT(length(w.position() - expected), 0.02f);
      const auto area = [&](const std::array<Vec3f, 6>& p) {
        return length(cross(p[corners[1]] - p[corners[0]], p[corners[2]] - p[corners[0]]));
      };
      EXPECT_NEAR(areaScale(f.window, v, next), area(then) / area(restPose), 0.03);
      ++moved;
    }
  }
  EXPECT_GT(moved, 20);
}

}  // namespace
}  // namespace pathfarm
