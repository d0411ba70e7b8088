// The specular manifold walk follows rigid motion only: over a deforming mirror (the
// skinned arm of gltf_arm.h made of chrome) it gives no motion, so those pixels are
// re-rendered rather than warped, while the same pose as a still mesh is tracked.
#include <gtest/gtest.h>

#include "renderer/accel/shot_geometry.h"
#include "renderer/decomposition/specular_motion.h"
#include "renderer/scene/scene_loader.h"
#include "test_support.h"
#include "tests/renderer/scene/gltf/gltf_arm.h"

namespace pathfarm {
namespace {

constexpr int kMirrorComponent = 2;  // reflection, in Decomposition::standard()

std::filesystem::path mirrorFolder() { return test_support::processTemporaryFolder("pathfarm_deforming_mirror"); }

// The arm as a mirror facing the camera, and behind the camera a diffuse wall it reflects.
gltftest::GltfBuilder mirrorArm(bool animated) {
  gltftest::GltfBuilder b = gltftest::skinnedArm({0, 1, 0}, animated);
  b.doc()["materials"] = {{{"pbrMetallicRoughness", {{"metallicFactor", 1}, {"roughnessFactor", 0}}}},
                          {{"pbrMetallicRoughness", {{"metallicFactor", 0}, {"roughnessFactor", 1}}}}};
  b.doc()["meshes"][0]["primitives"][0]["material"] = 0;
  const float back = std::sin(0.5f * kPi);  // half a turn about y: the wall faces -z
  const int wall =
      b.node({{"mesh", b.square(1)}, {"translation", {1, 0.5, 9}}, {"scale", {20, 20, 1}}, {"rotation", {0, back, 0, 0}}});
  b.doc()["scenes"][0]["nodes"].push_back(wall);
  return b;
}

struct ChainCounts {
  int chains = 0, tracked = 0;
};

ChainCounts countChains(const std::filesystem::path& file) {
  const Scene scene = loadScene(file);
  const EmbreeDevice device;
  const ShotGeometry shot(scene, device);
  const FrameGeometry frame(shot, 6);  // a quarter second in: the elbow turned 22.5 degrees
  const std::vector<PreciseShape> shapes = preciseShapesOf(scene);
  const Decomposition decomposition = Decomposition::standard();
  const SpecularMotion motion(frame, shapes, decomposition, 24, 24);
  ChainCounts counts;
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 24; ++x) {
      const SpecularTrack track = motion.track(x, y, kMirrorComponent);
      counts.chains += track.hasChain;
      counts.tracked += track.tracked();
    }
  return counts;
}

TEST(DeformingSpecular, AChainOverADeformingMirrorIsLeftToReRenderingAndAStillOneIsTracked) {
  gltftest::GltfBuilder deforming = mirrorArm(true), still = mirrorArm(false);
  const ChainCounts moving = countChains(deforming.write(mirrorFolder(), "mirror_deforming"));
  const ChainCounts posed = countChains(still.write(mirrorFolder(), "mirror_still"));
  EXPECT_GT(moving.chains, 20);
  EXPECT_EQ(moving.tracked, 0);
  EXPECT_GT(posed.chains, 20);
  EXPECT_EQ(posed.tracked, posed.chains);
}

}  // namespace
}  // namespace pathfarm
