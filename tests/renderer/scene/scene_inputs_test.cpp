// The files a scene load reads, as the recorder lists them for uploading: the scene file,
// textures, OBJ and PLY meshes, a glTF include with its buffer and image, an environment
// map outside the scene's folder — and nothing that merely lies beside them.
#include "renderer/scene/scene_inputs.h"

#include <gtest/gtest.h>
#include <stb_image_write.h>

#include <fstream>

#include "renderer/scene/gltf/gltf_builder.h"
#include "renderer/scene/scene_loader.h"
#include "test_support.h"

namespace pathfarm {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> inputsOf(const fs::path& scene) {
  const SceneInputRecorder recorder;
  loadScene(scene);
  return recorder.files();
}

TEST(SceneInputs, TexturesAndMeshesOfTheMaterialsScene) {
  const fs::path folder = test_support::sourceDir() / "scenes" / "materials";
  const std::vector<fs::path> expected = {folder / "checker.png", folder / "icosphere.obj", folder / "pyramid.ply",
                                          folder / "scene.json"};
  EXPECT_EQ(inputsOf(folder / "scene.json"), expected);
}

TEST(SceneInputs, AGlbIncludeAndASkyInASiblingFolder) {
  const fs::path scenes = test_support::sourceDir() / "scenes";
  const std::vector<fs::path> expected = {scenes / "showroom" / "scene.json", scenes / "showroom" / "showroom.glb",
                                          scenes / "sky" / "sky.hdr"};
  EXPECT_EQ(inputsOf(scenes / "showroom" / "scene.json"), expected);
}

TEST(SceneInputs, AGltfWithItsBufferAndImageButNotTheFilesBesideIt) {
  const fs::path folder = test_support::processTemporaryFolder("pathfarm_scene_inputs");
  fs::remove_all(folder);
  fs::create_directories(folder / "textures");
  const unsigned char texels[6] = {255, 0, 0, 0, 255, 0};
  ASSERT_NE(stbi_write_png((folder / "textures" / "two.png").c_str(), 2, 1, 3, texels, 6), 0);
  std::ofstream(folder / "unrelated.png") << "not read";
  gltftest::GltfBuilder b;
  b.doc()["images"] = {{{"uri", "textures/two.png"}}};
  b.doc()["textures"] = {{{"source", 0}}};
  b.doc()["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
  const int square = b.node({{"mesh", b.square(0)}});
  b.scene({square, b.camera({0, 0, 3})});
  const fs::path gltf = b.write(folder, "square");
  std::ofstream(folder / "scene.json") << R"({"include": "square.gltf", "render": {"resolution": [8, 8]}})";

  const std::vector<fs::path> expected = {folder / "scene.json", folder / "square.bin", folder / "square.gltf",
                                          folder / "textures" / "two.png"};
  EXPECT_EQ(inputsOf(folder / "scene.json"), expected);
  fs::remove_all(folder);
}

}  // namespace
}  // namespace pathfarm
