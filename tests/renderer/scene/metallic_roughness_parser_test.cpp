// The scene format's metallic_roughness material: every key lands in its Material field,
// the metallic-roughness texture is read as linear data and the base colour one as sRGB,
// and bad values are rejected with the key named.
#include <gtest/gtest.h>
#include <stb/stb_image_write.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "renderer/scene/scene_loader.h"
#include "test_support.h"

namespace pathfarm {
namespace {

namespace fs = std::filesystem;

std::string sceneWith(const std::string& material) {
  return R"({
    "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]},
    "materials": {"m": )" + material + R"(},
    "shapes": [{"type": "sphere", "radius": 1, "material": "m"}]
  })";
}

const Material& onlyMaterial(const Scene& scene) { return scene.materials.at(0); }

std::string materialErrorOf(const std::string& material, const fs::path& folder = fs::temp_directory_path()) {
  return test_support::sceneErrorOf([&] { test_support::sceneFromJson(sceneWith(material), folder); });
}

TEST(MetallicRoughnessParser, ReadsEveryKey) {
  const Scene scene = test_support::sceneFromJson(sceneWith(R"({"type": "metallic_roughness",
      "base_color": [0.9, 0.5, 0.1], "metallic": 0.25, "roughness": 0.4, "transmission": 0.75, "ior": 1.33})"));
  const Material& m = onlyMaterial(scene);
  EXPECT_EQ(m.type, MaterialType::MetallicRoughness);
  EXPECT_FLOAT_EQ(m.reflectance.r, 0.9f);
  EXPECT_FLOAT_EQ(m.reflectance.b, 0.1f);
  EXPECT_FLOAT_EQ(m.metallic, 0.25f);
  EXPECT_FLOAT_EQ(m.roughness, 0.4f);
  EXPECT_FLOAT_EQ(m.transmission, 0.75f);
  EXPECT_FLOAT_EQ(m.ior, 1.33f);
  EXPECT_EQ(m.reflectanceTexture, -1);
  EXPECT_EQ(m.metallicRoughnessTexture, -1);
}

// glTF's defaults: base colour 1, metallic 1, roughness 1, no transmission, ior 1.5.
TEST(MetallicRoughnessParser, DefaultsAreGltfs) {
  const Scene scene = test_support::sceneFromJson(sceneWith(R"({"type": "metallic_roughness"})"));
  const Material& m = onlyMaterial(scene);
  EXPECT_FLOAT_EQ(m.reflectance.g, 1);
  EXPECT_FLOAT_EQ(m.metallic, 1);
  EXPECT_FLOAT_EQ(m.roughness, 1);
  EXPECT_FLOAT_EQ(m.transmission, 0);
  EXPECT_FLOAT_EQ(m.ior, 1.5f);
}

class MetallicRoughnessTextures : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("pathfarm_mr_parser_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    // One texel: R 10, G 128, B 200.
    const std::vector<uint8_t> rgb{10, 128, 200};
    ASSERT_NE(stbi_write_png((dir_ / "t.png").string().c_str(), 1, 1, 3, rgb.data(), 3), 0);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  fs::path dir_;
};

TEST_F(MetallicRoughnessTextures, DataTextureIsLinearAndColourTextureSrgb) {
  const Scene scene = test_support::sceneFromJson(
      sceneWith(R"({"type": "metallic_roughness", "base_color": {"texture": "t.png"},
                    "metallic_roughness_texture": "t.png"})"),
      dir_);
  const Material& m = onlyMaterial(scene);
  ASSERT_GE(m.reflectanceTexture, 0);
  ASSERT_GE(m.metallicRoughnessTexture, 0);
  const Rgb data = scene.textures.at(size_t(m.metallicRoughnessTexture)).lookup({0.5f, 0.5f});
  EXPECT_NEAR(data.g, 128 / 255.0, 1e-6);
  EXPECT_NEAR(data.b, 200 / 255.0, 1e-6);
  // 128 through the sRGB curve is 0.2159, far from 0.502.
  const Rgb colour = scene.textures.at(size_t(m.reflectanceTexture)).lookup({0.5f, 0.5f});
  EXPECT_NEAR(colour.g, 0.21586, 1e-4);
  EXPECT_FLOAT_EQ(m.reflectance.g, 1);  // the factor the texture multiplies
}

TEST_F(MetallicRoughnessTextures, BadValuesAreRejectedByName) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"({"type": "metallic_roughness", "metallic": 1.5})", "materials.m.metallic: 1.5 is out of range [0, 1]"},
      {R"({"type": "metallic_roughness", "roughness": -0.1})", "materials.m.roughness: -0.1 is out of range [0, 1]"},
      {R"({"type": "metallic_roughness", "transmission": 2})", "materials.m.transmission: 2 is out of range [0, 1]"},
      {R"({"type": "metallic_roughness", "ior": 3.5})", "materials.m.ior: 3.5 is out of range [1, 3]"},
      {R"({"type": "metallic_roughness", "ior": 0.9})", "materials.m.ior: 0.9 is out of range [1, 3]"},
      {R"({"type": "metallic_roughness", "base_color": [0.5, 1.2, 0.5]})",
       "materials.m.base_color[1]: 1.2 is out of range [0, 1]"},
      {R"({"type": "metallic_roughness", "metallic": "shiny"})", "materials.m.metallic: expected a number"},
      {R"({"type": "metallic_roughness", "reflectance": 0.5})", "materials.m.reflectance: unknown key"},
      {R"({"type": "metallic_roughness", "alpha": 0.5})", "materials.m.alpha: unknown key"},
      {R"({"type": "metallic_roughness", "metallic_roughness_texture": "nope.png"})",
       "materials.m.metallic_roughness_texture: " + (dir_ / "nope.png").string()},
      {R"({"type": "metallic_roughness", "base_color": {"texture": "nope.png"}})",
       "materials.m.base_color.texture: " + (dir_ / "nope.png").string()},
      {R"({"type": "metallic_roughness", "base_color": {"file": "t.png"}})", "materials.m.base_color.file: unknown key"},
  };
  for (const auto& [material, expected] : cases) {
    const std::string message = materialErrorOf(material, dir_);
    EXPECT_NE(message.find(expected), std::string::npos) << "expected \"" << expected << "\" in \"" << message << "\"";
  }
}

}  // namespace
}  // namespace pathfarm
