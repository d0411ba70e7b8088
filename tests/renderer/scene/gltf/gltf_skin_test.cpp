// Characters from glTF: skins and morph targets posed as the glTF 2.0 specification
// defines them, checked against closed forms of the arm in gltf_arm.h and of a morphing
// triangle.
#include <gtest/gtest.h>

#include <cmath>

#include "renderer/scene/scene_loader.h"
#include "test_support.h"
#include "tests/renderer/scene/gltf/gltf_arm.h"

namespace pathfarm {
namespace {

using gltftest::GltfBuilder;
using test_support::expectNear;

std::filesystem::path skinFolder() { return test_support::processTemporaryFolder("pathfarm_gltf_skin"); }

const SceneObject& onlyMesh(const Scene& scene) {
  EXPECT_EQ(scene.objects.size(), 1u);
  return scene.objects.front();
}

// (x, y) turned by `radians` about z, and (x, z) about y, written out.
Vec3f turnedAboutZ(Vec3f p, double radians) {
  const float c = static_cast<float>(std::cos(radians)), s = static_cast<float>(std::sin(radians));
  return {p.x * c - p.y * s, p.x * s + p.y * c, p.z};
}
Vec3f turnedAboutY(Vec3f p, double radians) {
  const float c = static_cast<float>(std::cos(radians)), s = static_cast<float>(std::sin(radians));
  return {p.x * c + p.z * s, p.y, -p.x * s + p.z * c};
}

TEST(GltfSkin, VerticesFollowTheirJointsAsLinearBlendSkinningSays) {
  GltfBuilder b = gltftest::skinnedArm({0, 0, 1});
  const Scene scene = loadScene(b.write(skinFolder(), "arm_z"));
  const SceneObject& arm = onlyMesh(scene);
  ASSERT_TRUE(arm.deformation);
  EXPECT_FALSE(arm.transform.isAnimated());
  const Vec3f elbow{1, 0, 0};
  for (const double t : {0.0, 0.5, 1.0}) {
    SCOPED_TRACE(t);
    const double angle = 0.5 * kPi * t;  // the elbow's LINEAR slerp turns at a constant rate
    const MeshDeformation::Pose pose = arm.deformation->poseAt(t);
    const Vec3f hand = elbow + turnedAboutZ({1, 0, 0}, angle);
    const Vec3f innerElbow = (elbow + turnedAboutZ({0, 1, 0}, angle)) * 0.75f + Vec3f{1, 1, 0} * 0.25f;
    expectNear(pose.positions[0], {0, 0, 0}, 1e-5f);  // the shoulder's alone: never moves
    expectNear(pose.positions[2], hand, 1e-5f);
    expectNear(pose.positions[4], innerElbow, 1e-5f);
    expectNear(arm.deformation->positionAt(2, t), hand, 1e-5f);
    expectNear(arm.deformation->positionAt(4, t), innerElbow, 1e-5f);
    expectNear(pose.normals[2], {0, 0, 1}, 1e-5f);  // turning in the plane keeps it facing +z
  }
}

TEST(GltfSkin, NormalsTurnWithTheJointsAndStayUnit) {
  GltfBuilder b = gltftest::skinnedArm({0, 1, 0});
  const Scene scene = loadScene(b.write(skinFolder(), "arm_y"));
  const MeshDeformation::Pose pose = onlyMesh(scene).deformation->poseAt(1.0);
  expectNear(pose.positions[2], Vec3f{1, 0, 0} + turnedAboutY({1, 0, 0}, 0.5 * kPi), 1e-5f);
  expectNear(pose.normals[2], turnedAboutY({0, 0, 1}, 0.5 * kPi), 1e-5f);
  // Vertex 4 blends 3 : 1 a quarter turn about y with the identity. That linear map
  // scales the xz plane uniformly, so its inverse transpose turns the normal the way it
  // turns vectors: towards 0.75 (1, 0, 0) + 0.25 (0, 0, 1).
  const float norm = std::sqrt(0.75f * 0.75f + 0.25f * 0.25f);
  expectNear(pose.normals[4], {0.75f / norm, 0, 0.25f / norm}, 1e-5f);
  for (const Vec3f& n : pose.normals) EXPECT_NEAR(length(n), 1.0f, 1e-5f);
}

TEST(GltfSkin, MorphTargetsApplyBeforeTheSkin) {
  // The hand (vertex 2) lifted by 0.5 along y in the mesh's own space, at weight 1: the
  // elbow then turns the lifted hand.
  GltfBuilder b = gltftest::skinnedArm({0, 0, 1});
  std::vector<float> lift(18, 0.0f);
  lift[7] = 0.5f;
  b.doc()["meshes"][0]["primitives"][0]["targets"] = {{{"POSITION", b.floats(lift, "VEC3")}}};
  b.doc()["meshes"][0]["weights"] = {1.0};
  const Scene scene = loadScene(b.write(skinFolder(), "arm_morphed"));
  const SceneObject& arm = onlyMesh(scene);
  ASSERT_TRUE(arm.deformation);
  expectNear(arm.deformation->positionAt(2, 1.0), Vec3f{1, 0, 0} + turnedAboutZ({1, 0.5f, 0}, 0.5 * kPi), 1e-5f);
  expectNear(arm.deformation->poseAt(1.0).positions[2], {0.5f, 1, 0}, 1e-5f);
}

TEST(GltfSkin, AStillSkinIsPosedOnceIntoAStaticMesh) {
  GltfBuilder b = gltftest::skinnedArm({0, 0, 1}, false);
  const Scene scene = loadScene(b.write(skinFolder(), "arm_still"));
  const SceneObject& arm = onlyMesh(scene);
  EXPECT_FALSE(arm.deformation);
  EXPECT_FALSE(arm.moves());
  expectNear(arm.mesh->positions[2], {1, 1, 0}, 1e-5f);  // the hand, the elbow turned a quarter about z
  expectNear(arm.mesh->positions[5], {0, 1, 0}, 1e-5f);
}

// A triangle at z = 5 (its node's translation) whose first vertex rises by the weight
// of its one morph target, animated from 0 to 1 over the first second.
GltfBuilder morphingTriangle(const std::string& interpolation) {
  GltfBuilder b;
  const int position = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", true);
  const int rise = b.floats({0, 0, 1, 0, 0, 0, 0, 0, 0}, "VEC3");
  const int mesh = b.mesh({{"POSITION", position}});
  b.doc()["meshes"][0]["primitives"][0]["targets"] = {{{"POSITION", rise}}};
  const int node = b.node({{"mesh", mesh}, {"translation", {0, 0, 5}}});
  const int times = b.floats({0, 1}, "SCALAR");
  // CUBICSPLINE keys hold (in-tangent, value, out-tangent); flat tangents here.
  const int weights = b.floats(interpolation == "CUBICSPLINE" ? std::vector<float>{0, 0, 0, 0, 1, 0}
                                                              : std::vector<float>{0, 1},
                               "SCALAR");
  b.doc()["animations"] = {{{"samplers", {{{"input", times}, {"output", weights}, {"interpolation", interpolation}}}},
                            {"channels", {{{"sampler", 0}, {"target", {{"node", node}, {"path", "weights"}}}}}}}};
  b.scene({node, b.camera({0, 0, 9})});
  return b;
}

TEST(GltfMorph, TargetWeightsFollowLinearStepAndCubicSplineKeys) {
  // The weight at t for keys 0 -> 1 over [0, 1]: t, 0 until the last key, and the Hermite
  // blend 3t^2 - 2t^3 with flat tangents.
  const struct {
    const char* interpolation;
    double (*weight)(double);
  } cases[] = {{"LINEAR", [](double t) { return t; }},
               {"STEP", [](double t) { return t < 1 ? 0.0 : 1.0; }},
               {"CUBICSPLINE", [](double t) { return 3 * t * t - 2 * t * t * t; }}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.interpolation);
    GltfBuilder b = morphingTriangle(c.interpolation);
    const Scene scene = loadScene(b.write(skinFolder(), std::string("morph_") + c.interpolation));
    const SceneObject& triangle = onlyMesh(scene);
    ASSERT_TRUE(triangle.deformation);
    for (const double t : {0.0, 0.25, 0.6, 0.99, 1.0, 2.0}) {
      const float z = 5 + static_cast<float>(c.weight(std::min(t, 1.0)));
      expectNear(triangle.deformation->positionAt(0, t), {0, 0, z}, 1e-5f);
      expectNear(triangle.deformation->poseAt(t).positions[0], {0, 0, z}, 1e-5f);
      expectNear(triangle.deformation->poseAt(t).positions[1], {1, 0, 5}, 1e-6f);
    }
  }
}

TEST(GltfMorph, DefaultWeightsApplyWhenNothingAnimatesThemAndTheNodesOverrideTheMeshs) {
  GltfBuilder b = morphingTriangle("LINEAR");
  b.doc().erase("animations");
  b.doc()["meshes"][0]["weights"] = {0.5};
  const Scene fromMesh = loadScene(b.write(skinFolder(), "morph_mesh_weights"));
  EXPECT_FALSE(onlyMesh(fromMesh).deformation);  // never changes: posed once
  expectNear(onlyMesh(fromMesh).mesh->positions[0], {0, 0, 5.5f}, 1e-6f);
  b.doc()["nodes"][0]["weights"] = {0.25};
  const Scene fromNode = loadScene(b.write(skinFolder(), "morph_node_weights"));
  expectNear(onlyMesh(fromNode).mesh->positions[0], {0, 0, 5.25f}, 1e-6f);
}

TEST(GltfMorph, NormalAndTangentOffsetsBlendAndAreRenormalized) {
  GltfBuilder b;
  const int position = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", true);
  const int normal = b.floats({0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
  const int tangent = b.floats({1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1}, "VEC4");
  const int normalOffset = b.floats({0, 1, -1, 0, 1, -1, 0, 1, -1}, "VEC3");
  const int tangentOffset = b.floats({-1, 1, 0, -1, 1, 0, -1, 1, 0}, "VEC3");
  const int mesh = b.mesh({{"POSITION", position}, {"NORMAL", normal}, {"TANGENT", tangent}});
  b.doc()["meshes"][0]["primitives"][0]["targets"] = {{{"NORMAL", normalOffset}, {"TANGENT", tangentOffset}}};
  b.doc()["meshes"][0]["weights"] = {0.5};
  b.scene({b.node({{"mesh", mesh}}), b.camera({0, 0, 3})});
  const Scene scene = loadScene(b.write(skinFolder(), "morph_frames"));
  const TriangleMesh& posed = *onlyMesh(scene).mesh;
  // (0, 0, 1) + 0.5 (0, 1, -1) and (1, 0, 0) + 0.5 (-1, 1, 0), each made unit.
  const float half = std::sqrt(0.5f);
  expectNear(posed.normals[1], {0, half, half}, 1e-6f);
  expectNear(posed.tangents[1], {half, half, 0}, 1e-6f);
}

}  // namespace
}  // namespace pathfarm
