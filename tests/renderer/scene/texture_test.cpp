#include "renderer/scene/texture.h"

#include <gtest/gtest.h>
#include <stb/stb_image_write.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace pathfarm {
namespace {

namespace fs = std::filesystem;

class TextureTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("pathfarm_texture_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  // A 2x2 RGB PNG, rows top to bottom.
  fs::path writePng(const std::string& name, const std::vector<uint8_t>& rgb, int w, int h) const {
    const fs::path path = dir_ / name;
    EXPECT_NE(stbi_write_png(path.string().c_str(), w, h, 3, rgb.data(), w * 3), 0);
    return path;
  }

  fs::path dir_;
};

// Reference sRGB decoding, written independently of the implementation.
double srgbReference(int code) {
  const double c = code / 255.0;
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

void expectRgbNear(Rgb actual, Rgb expected, float tolerance) {
  EXPECT_NEAR(actual.r, expected.r, tolerance);
  EXPECT_NEAR(actual.g, expected.g, tolerance);
  EXPECT_NEAR(actual.b, expected.b, tolerance);
}

// Top row: (188,188,188) (0,0,0); bottom row: (255,255,255) (0,128,255).
const std::vector<uint8_t> kPixels = {188, 188, 188, 0, 0, 0, 255, 255, 255, 0, 128, 255};

TEST_F(TextureTest, PngIsSrgbDecodedWithTopRowAtVOne) {
  const ImageTexture tex = ImageTexture::load(writePng("a.png", kPixels, 2, 2));
  ASSERT_EQ(tex.width(), 2);
  ASSERT_EQ(tex.height(), 2);
  // Texel centers: u = 0.25 / 0.75, v = 0.75 (top row) / 0.25 (bottom row).
  const Rgb topLeft = tex.lookup({0.25f, 0.75f});
  EXPECT_NEAR(topLeft.r, 0.50289f, 2e-5f);  // 188/255 through the sRGB EOTF
  expectRgbNear(topLeft, Rgb(static_cast<float>(srgbReference(188))), 1e-6f);
  expectRgbNear(tex.lookup({0.75f, 0.75f}), Rgb(0.0f), 1e-6f);
  expectRgbNear(tex.lookup({0.25f, 0.25f}), Rgb(1.0f), 1e-6f);
  expectRgbNear(tex.lookup({0.75f, 0.25f}), Rgb(0.0f, static_cast<float>(srgbReference(128)), 1.0f),
                1e-6f);
  EXPECT_NEAR(srgbReference(128), 0.21586, 1e-5);
}

// Data textures (glTF's metallicRoughnessTexture) keep the code's fraction of full scale.
TEST_F(TextureTest, PngLoadedAsLinearDataIsNotSrgbDecoded) {
  const ImageTexture tex = ImageTexture::load(writePng("data.png", kPixels, 2, 2), TextureEncoding::Linear);
  expectRgbNear(tex.lookup({0.25f, 0.75f}), Rgb(188 / 255.0f), 1e-6f);
  expectRgbNear(tex.lookup({0.75f, 0.25f}), Rgb(0.0f, 128 / 255.0f, 1.0f), 1e-6f);
  // The default is still colour.
  EXPECT_NEAR(ImageTexture::load(dir_ / "data.png").lookup({0.25f, 0.75f}).r, srgbReference(188), 1e-6);
}

TEST_F(TextureTest, BilinearBetweenTexelCenters) {
  const ImageTexture tex = ImageTexture::load(writePng("b.png", kPixels, 2, 2));
  const float a = static_cast<float>(srgbReference(188));
  const float g = static_cast<float>(srgbReference(128));
  // Halfway between the two top texels.
  expectRgbNear(tex.lookup({0.5f, 0.75f}), Rgb(a * 0.5f), 1e-6f);
  // Halfway between the two left texels.
  expectRgbNear(tex.lookup({0.25f, 0.5f}), Rgb((a + 1.0f) * 0.5f), 1e-6f);
  // The middle of all four.
  expectRgbNear(tex.lookup({0.5f, 0.5f}), Rgb((a + 1.0f) / 4, (a + 1.0f + g) / 4, (a + 2.0f) / 4),
                1e-6f);
  // A quarter of the way from the top-left center to the top-right one.
  expectRgbNear(tex.lookup({0.375f, 0.75f}), Rgb(a * 0.75f), 1e-6f);
}

TEST_F(TextureTest, RepeatWrapping) {
  const ImageTexture tex = ImageTexture::load(writePng("c.png", kPixels, 2, 2));
  const float a = static_cast<float>(srgbReference(188));
  // u = 0 lies halfway between the right column (wrapped) and the left one.
  expectRgbNear(tex.lookup({0.0f, 0.75f}), Rgb(a * 0.5f), 1e-6f);
  expectRgbNear(tex.lookup({1.0f, 0.75f}), Rgb(a * 0.5f), 1e-6f);
  expectRgbNear(tex.lookup({3.25f, -1.25f}), tex.lookup({0.25f, 0.75f}), 1e-6f);
  expectRgbNear(tex.lookup({-0.75f, 2.25f}), tex.lookup({0.25f, 0.25f}), 1e-6f);
  // Out-of-range and non-finite coordinates stay in the image.
  EXPECT_TRUE(tex.lookup({1e30f, -1e30f}).isFinite());
  EXPECT_TRUE(tex.lookup({NAN, INFINITY}).isFinite());
}

TEST_F(TextureTest, HdrIsLinear) {
  const fs::path path = dir_ / "light.hdr";
  const float data[3] = {0.25f, 2.0f, 8.0f};
  ASSERT_NE(stbi_write_hdr(path.string().c_str(), 1, 1, 3, data), 0);
  const ImageTexture tex = ImageTexture::load(path);
  expectRgbNear(tex.lookup({0.3f, 0.6f}), Rgb(0.25f, 2.0f, 8.0f), 0.05f);
}

TEST_F(TextureTest, MissingFileNamesTheFile) {
  const fs::path path = dir_ / "missing.png";
  try {
    ImageTexture::load(path);
    FAIL() << "expected TextureError";
  } catch (const TextureError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path.string()), std::string::npos) << message;
    EXPECT_NE(message.find("fopen"), std::string::npos) << "stb's reason is missing: " << message;
  }
}

TEST_F(TextureTest, CorruptFileIsAnError) {
  const fs::path path = dir_ / "corrupt.png";
  std::ofstream(path, std::ios::binary) << "\x89PNG\r\n\x1a\n not really";
  EXPECT_THROW(ImageTexture::load(path), TextureError);
}

TEST(ImageTexture, ConstructorChecksSize) {
  EXPECT_THROW(ImageTexture(2, 2, std::vector<Rgb>(3)), TextureError);
  EXPECT_THROW(ImageTexture(0, 1, {}), TextureError);
  const ImageTexture tex(1, 1, {Rgb(0.5f, 0.25f, 1.0f)});
  expectRgbNear(tex.lookup({0.9f, 0.1f}), Rgb(0.5f, 0.25f, 1.0f), 0.0f);
}

}  // namespace
}  // namespace pathfarm

namespace pathfarm {
namespace {

// A 4 x 1 ramp 0, 1, 2, 3 (texel centres at u = 1/8, 3/8, 5/8, 7/8).
ImageTexture ramp(TextureWrap mode) {
  ImageTexture t(4, 1, {Rgb(0.0f), Rgb(1.0f), Rgb(2.0f), Rgb(3.0f)});
  t.setWrap(mode, mode);
  return t;
}

TEST(TextureWrapModes, RepeatClampAndMirrorOutsideTheUnitSquare) {
  // u = 1.125 is texel 0's centre one period on (repeat), past the edge (clamp: texel 3),
  // and mirrored back to u = 0.875, texel 3's centre (mirror).
  EXPECT_FLOAT_EQ(ramp(TextureWrap::Repeat).lookup({1.125f, 0.5f}).r, 0.0f);
  EXPECT_FLOAT_EQ(ramp(TextureWrap::Clamp).lookup({1.125f, 0.5f}).r, 3.0f);
  EXPECT_FLOAT_EQ(ramp(TextureWrap::Mirror).lookup({1.125f, 0.5f}).r, 3.0f);
  // u = -0.375 repeats to 0.625 (texel 2), clamps to 0 (texel 0), mirrors to 0.375 (texel 1).
  EXPECT_FLOAT_EQ(ramp(TextureWrap::Repeat).lookup({-0.375f, 0.5f}).r, 2.0f);
  EXPECT_FLOAT_EQ(ramp(TextureWrap::Clamp).lookup({-0.375f, 0.5f}).r, 0.0f);
  EXPECT_FLOAT_EQ(ramp(TextureWrap::Mirror).lookup({-0.375f, 0.5f}).r, 1.0f);
  // At the right edge (u = 1) repeat blends texels 3 and 0 halfway; clamp holds texel 3.
  EXPECT_FLOAT_EQ(ramp(TextureWrap::Repeat).lookup({0.9999f, 0.5f}).r, 3.0f * 0.5004f + 0.0f * 0.4996f);
  EXPECT_FLOAT_EQ(ramp(TextureWrap::Clamp).lookup({1.0f, 0.5f}).r, 3.0f);
}

}  // namespace
}  // namespace pathfarm
