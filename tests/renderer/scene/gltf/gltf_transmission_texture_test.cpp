// KHR_materials_transmission's transmissionTexture: a clear thin sheet whose texture lets
// light through on its left half only, in front of a lamp. Seen from the front, the sheet
// shows the lamp as (1 - F) x t(u) x Le, with F the Fresnel reflectance of ior 1.5 near
// normal incidence and t(u) the texture's red channel, and nothing where t = 0 (nothing
// lights its front side).
#include <gtest/gtest.h>
#include <stb_image_write.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "renderer/integrators/frame_renderer.h"
#include "renderer/integrators/path_vertex.h"
#include "renderer/scene/scene_loader.h"
#include "tests/renderer/scene/gltf/gltf_builder.h"
#include "test_support.h"

namespace pathfarm {
namespace {

using gltftest::GltfBuilder;

std::filesystem::path transmissionFolder() { return test_support::processTemporaryFolder("pathfarm_gltf_transmission"); }

// The 2 x 1 texture's red texels (1, 0; linear data) at u = 1/4 and 3/4, blended linearly
// between them and clamped beyond (CLAMP_TO_EDGE).
double transmissionAt(double u) { return std::clamp(1.5 - 2 * u, 0.0, 1.0); }

// The sheet: [-1, 1]^2 at z = 0 facing +z, u along +x; the lamp: a 6 x 6 emitter of
// radiance 1 at z = -1 facing the sheet; the camera at z = 2 seeing exactly the sheet.
std::filesystem::path writeScene() {
  const unsigned char texels[] = {255, 0, 0, 0, 0, 0};
  std::filesystem::create_directories(transmissionFolder());
  EXPECT_NE(stbi_write_png((transmissionFolder() / "half_clear.png").c_str(), 2, 1, 3, texels, 6), 0);
  GltfBuilder b;
  b.doc()["images"] = {{{"uri", "half_clear.png"}}};
  b.doc()["samplers"] = {{{"wrapS", 33071}, {"wrapT", 33071}}};
  b.doc()["textures"] = {{{"source", 0}, {"sampler", 0}}};
  b.doc()["extensionsUsed"] = {"KHR_materials_transmission"};
  b.doc()["materials"] = {
      {{"name", "sheet"},
       {"pbrMetallicRoughness", {{"metallicFactor", 0}, {"roughnessFactor", 0}}},
       {"extensions",
        {{"KHR_materials_transmission", {{"transmissionFactor", 1}, {"transmissionTexture", {{"index", 0}}}}}}}},
      {{"name", "lamp"}, {"emissiveFactor", {1, 1, 1}}}};
  const int sheet = b.node({{"mesh", b.square(0)}});
  const int lamp = b.node({{"mesh", b.square(1)}, {"translation", {0, 0, -1}}, {"scale", {3, 3, 1}}});
  b.scene({sheet, lamp, b.camera({0, 0, 2}, 2 * std::atan(0.5))});
  b.write(transmissionFolder(), "sheet");
  std::ofstream(transmissionFolder() / "sheet.json")
      << R"({"include": "sheet.gltf", "render": {"resolution": [16, 16], "spp": 256, "max_depth": 3}})";
  return transmissionFolder() / "sheet.json";
}

TEST(GltfTransmissionTexture, TheTextureScalesTheTransmissionFactor) {
  const Scene scene = loadScene(writeScene());
  const Material& sheet = scene.materials[0];
  ASSERT_EQ(sheet.type, MaterialType::MetallicRoughness);
  ASSERT_GE(sheet.transmissionTexture, 0);
  EXPECT_FLOAT_EQ(sheet.transmission, 1);
  for (const double u : {0.1, 0.4, 0.5, 0.6, 0.9})
    EXPECT_NEAR(surfaceAt(scene, sheet, {static_cast<float>(u), 0.5f}).transmission, transmissionAt(u), 1e-3) << u;
}

TEST(GltfTransmissionTexture, TheLampShowsThroughWhereTheTextureIsClear) {
  const Scene scene = loadScene(writeScene());
  const FrameImage image = FrameRenderer(scene, RenderSettings::defaultsOf(scene)).render(0);
  const auto& red = image.channel("R");
  const auto& variance = image.channel("variance.R");
  const double fresnel = 0.04;  // ((1.5 - 1) / (1.5 + 1))^2; within 1e-3 over this view
  for (int px = 0; px < 16; ++px) {
    // Column px sees x = -1 + (px + 0.5) / 8, so u = (px + 0.5) / 16; a pixel spans 1/16
    // of u, over which t changes by up to 1/8.
    const double u = (px + 0.5) / 16;
    for (const int py : {3, 8, 12}) {
      const size_t p = static_cast<size_t>(py) * 16 + static_cast<size_t>(px);
      const double expected = (1 - fresnel) * transmissionAt(u);
      EXPECT_NEAR(red[p], expected, 4 * std::sqrt(variance[p]) + 0.07) << "pixel " << px << ", " << py;
      if (u > 0.78) {
        EXPECT_EQ(red[p], 0) << "pixel " << px << ", " << py;
      }
    }
  }
}

}  // namespace
}  // namespace pathfarm
