// The glTF importer against files whose content the tests state: geometry, hierarchy,
// instancing, camera, materials and animation.
#include <gtest/gtest.h>

#include <cmath>

#include "renderer/accel/frame_geometry.h"
#include "renderer/scene/gltf/gltf_scene.h"
#include "renderer/scene/scene_loader.h"
#include "tests/renderer/scene/gltf/gltf_builder.h"
#include "test_support.h"

namespace pathfarm {
namespace {

using gltftest::GltfBuilder;
using test_support::expectNear;

std::filesystem::path testFolder(const std::string& name) {
  return test_support::processTemporaryFolder("pathfarm_gltf") / name;
}

TEST(GltfImport, SquareMeshKeepsPositionsNormalsAndFlipsV) {
  GltfBuilder b;
  const int camera = b.camera({0, 0, 3});
  b.scene({b.node({{"mesh", b.square()}}), camera});
  const Scene scene = loadScene(b.write(testFolder("square"), "square"));
  ASSERT_EQ(scene.objects.size(), 1u);
  const TriangleMesh& mesh = *scene.objects[0].mesh;
  ASSERT_EQ(mesh.positions.size(), 4u);
  EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
  expectNear(mesh.positions[2], {1, 1, 0});
  expectNear(mesh.normals[0], {0, 0, 1});
  // glTF's (0, 1) is the image's bottom-left, pathfarm's v = 0 there too.
  EXPECT_FLOAT_EQ(mesh.uvs[0].x, 0);
  EXPECT_FLOAT_EQ(mesh.uvs[0].y, 0);
  EXPECT_FLOAT_EQ(mesh.uvs[2].y, 1);
  // Without animation: one frame, the camera's aspect ratio in the resolution.
  EXPECT_EQ(scene.defaults.frameEnd, 0);
  EXPECT_EQ(scene.defaults.width, scene.defaults.height);
}

TEST(GltfImport, HierarchyComposesTranslationRotationAndScale) {
  GltfBuilder b;
  // Child: scaled by 2 and moved 1 along x; parent: turned 90 degrees about z and moved
  // up by 5. The child's local point (1, 0, 0) lands at parent(child(p)):
  // child: (2*1 + 1, 0, 0) = (3, 0, 0); parent: rotate to (0, 3, 0), translate (0, 8, 0).
  const int child = b.node({{"mesh", b.square()}, {"translation", {1, 0, 0}}, {"scale", {2, 2, 2}}});
  const float s = std::sqrt(0.5f);
  const int parent = b.node({{"children", {child}}, {"rotation", {0, 0, s, s}}, {"translation", {0, 5, 0}}});
  b.scene({parent, b.camera({0, 0, 10})});
  const Scene scene = loadScene(b.write(testFolder("hierarchy"), "hierarchy"));
  ASSERT_EQ(scene.objects.size(), 1u);
  const Transform world = scene.objects[0].transform.transformAt(0);
  expectNear(world.point({1, 0, 0}), {0, 8, 0}, 1e-5f);
  expectNear(world.point({0, 1, 0}), {-2, 6, 0}, 1e-5f);
}

TEST(GltfImport, MatrixNodesAndMirrorsAreDecomposed) {
  GltfBuilder b;
  // Column-major: x mirrored, translation (1, 2, 3).
  const int node = b.node({{"mesh", b.square()},
                           {"matrix", {-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1, 2, 3, 1}}});
  b.scene({node, b.camera({0, 0, 10})});
  const Scene scene = loadScene(b.write(testFolder("matrix"), "matrix"));
  const Transform world = scene.objects[0].transform.transformAt(0);
  expectNear(world.point({1, 1, 1}), {0, 3, 4});
}

TEST(GltfImport, AMeshUsedByManyNodesIsSharedNotCopied) {
  GltfBuilder b;
  const int mesh = b.square();
  const int a = b.node({{"mesh", mesh}, {"translation", {-2, 0, 0}}});
  const int c = b.node({{"mesh", mesh}, {"translation", {2, 0, 0}}});
  b.scene({a, c, b.camera({0, 0, 10})});
  const Scene scene = loadScene(b.write(testFolder("shared"), "shared"));
  ASSERT_EQ(scene.objects.size(), 2u);
  EXPECT_EQ(scene.objects[0].mesh.get(), scene.objects[1].mesh.get());
  EXPECT_NE(scene.objects[0].objectId, scene.objects[1].objectId);
  // The ray tracer places both with one BVH (tests/renderer/accel/instancing_test.cpp).
  const EmbreeDevice device;
  const ShotGeometry shot(scene, device);
  EXPECT_TRUE(shot.shape(0).instanced && shot.shape(1).instanced);
  EXPECT_EQ(shot.objectScene(0), shot.objectScene(1));
  const FrameGeometry frame(shot, 0);
  for (const float x : {-2.0f, 2.0f}) {
    SurfaceHit hit;
    ASSERT_TRUE(frame.intersect({{x + 0.5f, 0.25f, 5}, {0, 0, -1}}, 0.5f, hit));
    EXPECT_EQ(hit.object, x < 0 ? 0 : 1);
    EXPECT_NEAR(hit.distance, 5, 1e-5);
  }
}

TEST(GltfImport, CameraFieldOfViewAndPlacementComeFromTheNode) {
  GltfBuilder b;
  const int camera = b.camera({1, 2, 3}, 0.5, 2.0);
  b.scene({b.node({{"mesh", b.square()}}), camera});
  const Scene scene = loadScene(b.write(testFolder("camera"), "camera"));
  EXPECT_NEAR(scene.camera.fovDegrees, 0.5 * 180 / 3.14159265358979, 1e-4);
  expectNear(scene.camera.transform.at(0).translation, {1, 2, 3});
  EXPECT_EQ(scene.defaults.width, 2 * scene.defaults.height);
  // Looking along -z: the camera-to-world rotation maps -z to -z.
  expectNear(scene.camera.transform.at(0).rotation.rotate({0, 0, -1}), {0, 0, -1});
}

TEST(GltfImport, MaterialFactorsAndExtensionsReachTheMaterial) {
  GltfBuilder b;
  b.doc()["materials"] = {
      {{"name", "copper"},
       {"pbrMetallicRoughness", {{"baseColorFactor", {0.9, 0.5, 0.3, 1}}, {"metallicFactor", 1}, {"roughnessFactor", 0.3}}}},
      {{"name", "glass"},
       {"pbrMetallicRoughness", {{"metallicFactor", 0}, {"roughnessFactor", 0}}},
       {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 1}}}, {"KHR_materials_ior", {{"ior", 1.33}}}}}},
      {{"name", "lamp"},
       {"emissiveFactor", {1, 0.5, 0.25}},
       {"extensions",
        {{"KHR_materials_emissive_strength", {{"emissiveStrength", 8}}},
         {"KHR_materials_specular", {{"specularFactor", 0.25}, {"specularColorFactor", {0, 0.5, 2}}}}}}}};
  const int copper = b.node({{"mesh", b.square(0)}});
  const int glass = b.node({{"mesh", b.square(1)}});
  const int lamp = b.node({{"mesh", b.square(2)}});
  b.scene({copper, glass, lamp, b.camera({0, 0, 10})});
  const Scene scene = loadScene(b.write(testFolder("materials"), "materials"));
  ASSERT_EQ(scene.objects.size(), 3u);
  const Material& m0 = scene.materials[static_cast<size_t>(scene.objects[0].material)];
  EXPECT_EQ(m0.type, MaterialType::MetallicRoughness);
  EXPECT_FLOAT_EQ(m0.reflectance.g, 0.5f);
  EXPECT_FLOAT_EQ(m0.metallic, 1);
  EXPECT_FLOAT_EQ(m0.roughness, 0.3f);
  EXPECT_EQ(scene.materialNames[static_cast<size_t>(scene.objects[0].material)], "copper");
  const Material& m1 = scene.materials[static_cast<size_t>(scene.objects[1].material)];
  EXPECT_FLOAT_EQ(m1.transmission, 1);
  EXPECT_FLOAT_EQ(m1.ior, 1.33f);
  EXPECT_TRUE(scene.objects[0].emission.isBlack());
  EXPECT_FLOAT_EQ(scene.objects[2].emission.r, 8);
  EXPECT_FLOAT_EQ(scene.objects[2].emission.b, 2);
  EXPECT_FLOAT_EQ(m1.specular, 1);  // without the extension: glTF's dielectric specular layer
  const Material& m2 = scene.materials[static_cast<size_t>(scene.objects[2].material)];
  EXPECT_FLOAT_EQ(m2.specular, 0.25f);
  EXPECT_FLOAT_EQ(m2.dielectricSpecularColor.r, 0);
  EXPECT_FLOAT_EQ(m2.dielectricSpecularColor.b, 2);
}

TEST(GltfImport, AVolumeMakesAFullyTransmissiveSurfaceASolidDielectric) {
  GltfBuilder b;
  const nlohmann::json volume = {{"KHR_materials_transmission", {{"transmissionFactor", 1}}},
                                 {"KHR_materials_ior", {{"ior", 1.4}}},
                                 {"KHR_materials_volume", {{"thicknessFactor", 1}}}};
  b.doc()["materials"] = {
      {{"pbrMetallicRoughness", {{"metallicFactor", 0}, {"roughnessFactor", 0}}}, {"extensions", volume}},
      {{"pbrMetallicRoughness", {{"metallicFactor", 0}, {"roughnessFactor", 0.5}}}, {"extensions", volume}},
      {{"pbrMetallicRoughness", {{"metallicFactor", 0}}},
       {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 1}}}}}}};
  b.scene({b.node({{"mesh", b.square(0)}}), b.node({{"mesh", b.square(1)}}), b.node({{"mesh", b.square(2)}}),
           b.camera({0, 0, 10})});
  const Scene scene = loadScene(b.write(testFolder("volume"), "volume"));
  const auto material = [&](size_t i) { return scene.materials[static_cast<size_t>(scene.objects[i].material)]; };
  EXPECT_EQ(material(0).type, MaterialType::Dielectric);
  EXPECT_FLOAT_EQ(material(0).ior, 1.4f);
  EXPECT_EQ(material(1).type, MaterialType::RoughDielectric);
  EXPECT_FLOAT_EQ(material(1).alpha, 0.25f);
  // Without a volume, glTF transmission is thin-walled: the metallic-roughness material.
  EXPECT_EQ(material(2).type, MaterialType::MetallicRoughness);
}

TEST(GltfImport, PrimitivesWithoutMaterialGetTheGltfDefault) {
  GltfBuilder b;
  b.scene({b.node({{"mesh", b.square()}}), b.camera({0, 0, 10})});
  const Scene scene = loadScene(b.write(testFolder("default_material"), "default_material"));
  const Material& m = scene.materials[static_cast<size_t>(scene.objects[0].material)];
  EXPECT_EQ(m.type, MaterialType::MetallicRoughness);
  EXPECT_FLOAT_EQ(m.reflectance.r, 1);
  EXPECT_FLOAT_EQ(m.metallic, 1);
  EXPECT_FLOAT_EQ(m.roughness, 1);
}

// A node moving along x with the given sampler, keys at 0 s and 1 s.
Scene animatedScene(const std::string& name, const std::string& interpolation, const std::vector<float>& values) {
  GltfBuilder b;
  const int node = b.node({{"mesh", b.square()}});
  b.scene({node, b.camera({0, 0, 10})});
  const int input = b.floats({0, 1}, "SCALAR");
  const int output = b.floats(values, "VEC3");
  b.doc()["animations"] = {{{"samplers", {{{"input", input}, {"output", output}, {"interpolation", interpolation}}}},
                            {"channels", {{{"sampler", 0}, {"target", {{"node", node}, {"path", "translation"}}}}}}}};
  return loadScene(b.write(testFolder(name), name));
}

TEST(GltfImport, LinearTranslationInterpolatesBetweenKeys) {
  const Scene scene = animatedScene("linear", "LINEAR", {0, 0, 0, 4, 0, 0});
  EXPECT_NEAR(scene.objects[0].transform.at(0.25).translation.x, 1.0f, 1e-5f);
  EXPECT_NEAR(scene.objects[0].transform.at(2.0).translation.x, 4.0f, 1e-5f);  // held after the last key
  EXPECT_EQ(scene.defaults.frameEnd, 24);  // 1 s at the default 24 fps
}

TEST(GltfImport, StepHoldsTheValueUntilTheNextKey) {
  const Scene scene = animatedScene("step", "STEP", {0, 0, 0, 4, 0, 0});
  EXPECT_NEAR(scene.objects[0].transform.at(0.9).translation.x, 0.0f, 1e-5f);
  EXPECT_NEAR(scene.objects[0].transform.at(1.0).translation.x, 4.0f, 1e-5f);
}

TEST(GltfImport, CubicSplineFollowsTheHermiteCurve) {
  // Keys (in-tangent, value, out-tangent): p0 = 0 with out-tangent 8, p1 = 4 with
  // in-tangent -8, over 1 s. Hermite at t: (2t^3-3t^2+1) p0 + (t^3-2t^2+t) m0 +
  // (-2t^3+3t^2) p1 + (t^3-t^2) m1; at t = 0.5: 0.125*8 + 0.5*4 - 0.125*(-8) = 4;
  // at t = 0.25: 0.140625*8 + 0.15625*4 + (-0.046875)*(-8) = 2.125.
  const Scene scene = animatedScene("cubic", "CUBICSPLINE", {0, 0, 0, 0, 0, 0, 8, 0, 0, -8, 0, 0, 4, 0, 0, 0, 0, 0});
  EXPECT_NEAR(scene.objects[0].transform.at(0.5).translation.x, 4.0f, 1e-4f);
  // 0.25 s lies on the importer's 1/96 s grid, so the sampled curve meets it exactly.
  EXPECT_NEAR(scene.objects[0].transform.at(0.25).translation.x, 2.125f, 1e-4f);
}

TEST(GltfImport, AnAnimatedParentMovesItsChildAndTheCamera) {
  GltfBuilder b;
  const int child = b.node({{"mesh", b.square()}, {"translation", {0, 1, 0}}});
  const int camera = b.camera({0, 0, 5});
  const int parent = b.node({{"children", {child, camera}}});
  b.scene({parent});
  const int input = b.floats({0, 2}, "SCALAR");
  const int output = b.floats({0, 0, 0, 0, 0, -6}, "VEC3");
  b.doc()["animations"] = {{{"samplers", {{{"input", input}, {"output", output}}}},
                            {"channels", {{{"sampler", 0}, {"target", {{"node", parent}, {"path", "translation"}}}}}}}};
  const Scene scene = loadScene(b.write(testFolder("parent_animation"), "parent_animation"));
  expectNear(scene.objects[0].transform.at(1.0).translation, {0, 1, -3});
  expectNear(scene.camera.transform.at(1.0).translation, {0, 0, 2});
  EXPECT_TRUE(scene.camera.transform.isAnimated());
}

TEST(GltfImport, JsonSceneIncludesAGltfFileAndOverridesByName) {
  GltfBuilder b;
  b.doc()["materials"] = {{{"name", "floor"}, {"pbrMetallicRoughness", {{"metallicFactor", 0}}}}};
  b.scene({b.node({{"mesh", b.square(0)}}), b.camera({0, 0, 10})});
  const std::filesystem::path folder = testFolder("include");
  b.write(folder, "set");
  const Scene scene = parseScene(R"({
    "include": {"file": "set.gltf", "shutter": [0, 0.5]}, "fps": 30,
    "render": {"resolution": [64, 32], "spp": 4},
    "materials": {"floor": {"type": "diffuse", "reflectance": 0.25}, "extra": {"type": "diffuse"}},
    "environment": {"radiance": 1},
    "shapes": [{"type": "sphere", "radius": 0.5, "material": "extra"}]
  })", folder / "shot.json");
  EXPECT_EQ(scene.fps, 30);
  EXPECT_FLOAT_EQ(scene.camera.shutterClose, 0.5f);
  EXPECT_EQ(scene.defaults.width, 64);
  ASSERT_EQ(scene.objects.size(), 2u);
  const Material& floor = scene.materials[static_cast<size_t>(scene.objects[0].material)];
  EXPECT_EQ(floor.type, MaterialType::Diffuse);
  EXPECT_FLOAT_EQ(floor.reflectance.r, 0.25f);
  EXPECT_EQ(scene.objects[1].type, ShapeType::Sphere);
  EXPECT_NE(scene.objects[0].objectId, scene.objects[1].objectId);
  EXPECT_FLOAT_EQ(scene.environment.radiance({0, 1, 0}).r, 1);
}

}  // namespace
}  // namespace pathfarm
