// Bad glTF input gets a SceneError naming the file and the JSON pointer of the fault,
// never a crash, a hang or a silently wrong scene.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>

#include "renderer/scene/scene_loader.h"
#include "test_support.h"
#include "tests/renderer/scene/gltf/gltf_arm.h"
#include "tests/renderer/scene/gltf/gltf_builder.h"

namespace pathfarm {
namespace {

using gltftest::GltfBuilder;

std::filesystem::path errorsFolder() { return test_support::processTemporaryFolder("pathfarm_gltf_errors"); }

// A valid scene to break: a square (accessors 0-3: position, normal, uv, indices) and
// a camera.
GltfBuilder validScene() {
  GltfBuilder b;
  b.scene({b.node({{"mesh", b.square()}}), b.camera({0, 0, 3})});
  return b;
}

// Loads the file and returns the error message ("" when it loaded).
std::string loadError(const std::filesystem::path& file) {
  return test_support::sceneErrorOf([&] { loadScene(file); });
}

std::string loadError(GltfBuilder& b, const std::string& name) { return loadError(b.write(errorsFolder(), name)); }

void expectError(const std::string& message, const std::string& file, const std::string& pointer,
                 const std::string& words) {
  EXPECT_NE(message.find(file), std::string::npos) << message;
  EXPECT_NE(message.find(pointer), std::string::npos) << message;
  EXPECT_NE(message.find(words), std::string::npos) << message;
}

TEST(GltfErrors, TheValidSceneLoads) {
  GltfBuilder b = validScene();
  EXPECT_EQ(loadError(b, "valid"), "(no error)");
}

TEST(GltfErrors, MalformedJson) {
  std::filesystem::create_directories(errorsFolder());
  std::ofstream(errorsFolder() / "broken.gltf") << "{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [";
  expectError(loadError(errorsFolder() / "broken.gltf"), "broken.gltf", "", "not a loadable glTF");
}

TEST(GltfErrors, MissingFileAndMissingBuffer) {
  expectError(loadError(errorsFolder() / "absent.glb"), "absent.glb", "", "cannot open");
  GltfBuilder b = validScene();
  const auto file = b.write(errorsFolder(), "nobin");
  std::filesystem::remove(errorsFolder() / "nobin.bin");
  expectError(loadError(file), "nobin.gltf", "", "not a loadable glTF");
}

TEST(GltfErrors, AccessorPastItsBuffer) {
  GltfBuilder b = validScene();
  b.doc()["accessors"][0]["count"] = 1000;
  expectError(loadError(b, "overrun"), "overrun.gltf", "/meshes/0/primitives/0/attributes/POSITION", "overrun");
}

TEST(GltfErrors, IndexPastTheVertexCount) {
  GltfBuilder b;
  const int position = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", true);
  b.scene({b.node({{"mesh", b.mesh({{"POSITION", position}}, b.indices(std::vector<uint16_t>{0, 1, 7}))}}),
           b.camera({0, 0, 3})});
  expectError(loadError(b, "badindex"), "badindex.gltf", "/meshes/0/primitives/0/indices", "index 7");
}

TEST(GltfErrors, NanPosition) {
  GltfBuilder b;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const int position = b.floats({0, 0, 0, 1, 0, 0, 0, nan, 0}, "VEC3");
  b.scene({b.node({{"mesh", b.mesh({{"POSITION", position}})}}), b.camera({0, 0, 3})});
  expectError(loadError(b, "nan"), "nan.gltf", "/attributes/POSITION", "non-finite");
}

TEST(GltfErrors, DegenerateNormal) {
  GltfBuilder b;
  const int position = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", true);
  const int normal = b.floats({0, 0, 1, 0, 0, 0, 0, 0, 1}, "VEC3");
  b.scene({b.node({{"mesh", b.mesh({{"POSITION", position}, {"NORMAL", normal}})}}), b.camera({0, 0, 3})});
  expectError(loadError(b, "zeronormal"), "zeronormal.gltf", "/attributes/NORMAL", "zero length");
}

TEST(GltfErrors, OnlyZeroAreaTrianglesLeaveNothingToRender) {
  GltfBuilder b;
  const int position = b.floats({0, 0, 0, 1, 0, 0, 2, 0, 0}, "VEC3", true);  // collinear
  b.scene({b.node({{"mesh", b.mesh({{"POSITION", position}})}}), b.camera({0, 0, 3})});
  expectError(loadError(b, "flat"), "flat.gltf", "", "no mesh with triangles");
}

TEST(GltfErrors, UnsupportedRequiredExtension) {
  GltfBuilder b = validScene();
  b.doc()["extensionsUsed"] = {"EXT_meshopt_compression"};
  b.doc()["extensionsRequired"] = {"EXT_meshopt_compression"};
  expectError(loadError(b, "required"), "required.gltf", "/extensionsRequired/0", "EXT_meshopt_compression");
}

TEST(GltfErrors, BadSkinsAndMorphTargetsAreRefusedByPointer) {
  const std::string attributes = "/meshes/0/primitives/0/attributes";
  GltfBuilder outside = gltftest::skinnedArm({0, 0, 1});
  outside.doc()["skins"][0]["joints"] = {outside.doc()["skins"][0]["joints"][0]};  // the elbow's joint 1 is gone
  outside.doc()["skins"][0]["inverseBindMatrices"] =
      outside.floats({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, "MAT4");
  expectError(loadError(outside, "outside"), "outside.gltf", attributes + "/JOINTS_0", "outside the skin's 1 joints");

  GltfBuilder weightless = gltftest::skinnedArm({0, 0, 1});
  weightless.doc()["accessors"][3].erase("bufferView");  // WEIGHTS_0 all zero
  expectError(loadError(weightless, "weightless"), "weightless.gltf", attributes + "/WEIGHTS_0",
              "vertex 0 has no joint weight");

  GltfBuilder unpaired = gltftest::skinnedArm({0, 0, 1});
  unpaired.doc()["meshes"][0]["primitives"][0]["attributes"].erase("WEIGHTS_0");
  expectError(loadError(unpaired, "unpaired"), "unpaired.gltf", attributes, "JOINTS_0 without WEIGHTS_0");

  GltfBuilder glowing = gltftest::skinnedArm({0, 0, 1});
  glowing.doc()["materials"] = {{{"emissiveFactor", {1, 1, 1}}}};
  glowing.doc()["meshes"][0]["primitives"][0]["material"] = 0;
  expectError(loadError(glowing, "glowing"), "glowing.gltf", "/materials", "emits light and deforms");

  GltfBuilder miscounted = validScene();
  miscounted.doc()["meshes"][0]["primitives"][0]["targets"] = {{{"POSITION", 0}}};
  miscounted.doc()["meshes"][0]["weights"] = {0.5, 0.5};
  expectError(loadError(miscounted, "miscounted"), "miscounted.gltf", "/meshes/0/weights",
              "2 weights for 1 morph targets");
}

TEST(GltfErrors, AbsurdCountIsRefusedBeforeAllocating) {
  GltfBuilder b = validScene();
  b.doc()["accessors"][0].erase("bufferView");  // an all-zero accessor of any size
  b.doc()["accessors"][0]["count"] = 4'000'000'000LL;
  expectError(loadError(b, "huge"), "huge.gltf", "/accessors/0", "exceeds the limit");
}

TEST(GltfErrors, AbsurdKeyTimesAreRefusedNotSampled) {
  // Found by the fuzzer: a cubic key at 1.8e33 s asked for that many samples.
  GltfBuilder b = validScene();
  const int input = b.floats({0, 1.8e33f}, "SCALAR");
  const int output = b.floats(std::vector<float>(18, 0.0f), "VEC3");
  b.doc()["animations"] = {{{"samplers", {{{"input", input}, {"output", output}, {"interpolation", "CUBICSPLINE"}}}},
                            {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}}}}};
  expectError(loadError(b, "longtime"), "longtime.gltf", "/animations/0/samplers/0/input", "key times");
}

TEST(GltfErrors, HierarchyCycle) {
  GltfBuilder b = validScene();
  b.doc()["nodes"][0]["children"] = {1};
  b.doc()["nodes"][1]["children"] = {0};
  const std::string message = loadError(b, "cycle");
  EXPECT_NE(message.find("cycle.gltf"), std::string::npos) << message;
  EXPECT_TRUE(message.find("cycle") != std::string::npos || message.find("more than one parent") != std::string::npos)
      << message;
}

TEST(GltfErrors, SceneWithoutCamera) {
  GltfBuilder b;
  b.scene({b.node({{"mesh", b.square()}})});
  expectError(loadError(b, "nocamera"), "nocamera.gltf", "/cameras", "no camera");
}

TEST(GltfErrors, OutOfRangeMaterialFactor) {
  GltfBuilder b = validScene();
  b.doc()["materials"] = {{{"pbrMetallicRoughness", {{"roughnessFactor", 7}}}}};
  b.doc()["meshes"][0]["primitives"][0]["material"] = 0;
  const std::string message = loadError(b, "factor");
  EXPECT_NE(message.find("factor.gltf"), std::string::npos) << message;
}

TEST(GltfErrors, ASpecularFactorOutOfRangeIsRefusedByPointer) {
  GltfBuilder b = validScene();
  b.doc()["materials"] = {{{"extensions", {{"KHR_materials_specular", {{"specularColorFactor", {1, -1, 1}}}}}}}};
  b.doc()["meshes"][0]["primitives"][0]["material"] = 0;
  const std::string message = loadError(b, "specular");
  EXPECT_NE(message.find("/materials/0/extensions/KHR_materials_specular/specularColorFactor/1"), std::string::npos)
      << message;
}

TEST(GltfErrors, IncludeOfAMissingFileNamesTheJsonKey) {
  try {
    parseScene(R"({"include": "nowhere.glb", "environment": {"radiance": 1}})", errorsFolder() / "shot.json");
    FAIL() << "expected a SceneError";
  } catch (const SceneError& e) {
    expectError(e.what(), "shot.json", "include", "nowhere.glb");
  }
}

}  // namespace
}  // namespace pathfarm
