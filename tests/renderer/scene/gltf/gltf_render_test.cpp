// Imported glTF scenes render what their files describe, checked against closed forms:
// a diffuse plate under a uniform sky reflects albedo x sky, an emitter seen directly
// shows its emission, and textures decode as the file's colour space says.
#include <gtest/gtest.h>
#include <stb_image_write.h>

#include <cmath>

#include "renderer/integrators/frame_renderer.h"
#include "renderer/scene/scene_loader.h"
#include "test_support.h"
#include "tests/renderer/scene/gltf/gltf_builder.h"

namespace pathfarm {
namespace {

using gltftest::GltfBuilder;

std::filesystem::path renderFolder() { return test_support::processTemporaryFolder("pathfarm_gltf_render"); }

// The sRGB decoding of an 8-bit value, by the IEC 61966-2-1 formula.
double srgbDecoded(int v) {
  const double c = v / 255.0;
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

// Mean of channel G over the pixels whose centres map, on the plane z = 0 seen by the
// glTF camera at (0, 0, 4) with a 4 x 4 view of it, into [x0, x1] x [y0, y1].
double meanOver(const FrameImage& image, double x0, double x1, double y0, double y1) {
  const auto& g = image.channel("G");
  double sum = 0;
  int count = 0;
  for (int py = 0; py < image.height(); ++py)
    for (int px = 0; px < image.width(); ++px) {
      const double x = (px + 0.5) / image.width() * 4 - 2, y = 2 - (py + 0.5) / image.height() * 4;
      if (x < x0 || x > x1 || y < y0 || y > y1) continue;
      sum += g[static_cast<size_t>(py) * static_cast<size_t>(image.width()) + static_cast<size_t>(px)];
      ++count;
    }
  EXPECT_GT(count, 10);
  return sum / count;
}

TEST(GltfRender, PlateLampAndSkyLandWhereTheCameraSeesThem) {
  GltfBuilder b;
  b.doc()["materials"] = {{{"name", "plate"}},
                          {{"name", "lamp"},
                           {"emissiveFactor", {1, 1, 1}},
                           {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 3}}}}}}};
  b.doc()["extensionsUsed"] = {"KHR_materials_emissive_strength"};
  // The plate fills x in [-1.9, -0.1], the lamp x in [0.1, 1.9], both |y| <= 0.9, at z = 0.
  const int plate = b.node({{"mesh", b.square(0)}, {"translation", {-1, 0, 0}}, {"scale", {0.9, 0.9, 1}}});
  const int lamp = b.node({{"mesh", b.square(1)}, {"translation", {1, 0, 0}}, {"scale", {0.9, 0.9, 1}}});
  b.scene({plate, lamp, b.camera({0, 0, 4}, 2 * std::atan(0.5))});
  b.write(renderFolder(), "plate");
  // Lambertian plate of albedo 0.5 and a black lamp body, under a sky of radiance 1.
  const Scene scene = parseScene(R"({
    "include": "plate.gltf",
    "materials": {"plate": {"type": "diffuse", "reflectance": 0.5}, "lamp": {"type": "diffuse", "reflectance": 0}},
    "environment": {"radiance": 1}
  })", renderFolder() / "shot.json");
  RenderSettings settings = RenderSettings::defaultsOf(scene);
  settings.width = settings.height = 40;
  settings.spp = 16;
  const FrameImage image = FrameRenderer(scene, settings).render(0);
  // Inner regions, a pixel and more away from every edge.
  EXPECT_NEAR(meanOver(image, -1.7, -0.3, -0.7, 0.7), 0.5, 0.02);
  EXPECT_NEAR(meanOver(image, 0.3, 1.7, -0.7, 0.7), 3.0, 1e-4);
  EXPECT_NEAR(meanOver(image, -2, 2, 1.1, 2), 1.0, 1e-4);
}

TEST(GltfRender, BaseColourTexturesAreSrgbAndMetallicRoughnessTexturesLinear) {
  // A 2 x 1 image: texel 0 = (255, 128, 0), texel 1 = (64, 64, 64).
  const unsigned char pixels[] = {255, 128, 0, 64, 64, 64};
  std::filesystem::create_directories(renderFolder());
  ASSERT_NE(stbi_write_png((renderFolder() / "texels.png").c_str(), 2, 1, 3, pixels, 6), 0);
  GltfBuilder b;
  b.doc()["images"] = {{{"uri", "texels.png"}}};
  b.doc()["textures"] = {{{"source", 0}}};
  b.doc()["materials"] = {{{"pbrMetallicRoughness",
                            {{"baseColorTexture", {{"index", 0}}}, {"metallicRoughnessTexture", {{"index", 0}}}}}}};
  b.scene({b.node({{"mesh", b.square(0)}}), b.camera({0, 0, 3})});
  const Scene scene = loadScene(b.write(renderFolder(), "textured"));
  const Material& m = scene.materials[static_cast<size_t>(scene.objects[0].material)];
  ASSERT_GE(m.reflectanceTexture, 0);
  ASSERT_GE(m.metallicRoughnessTexture, 0);
  // Texel 0's centre is u = 0.25 (v anywhere in a one-row image).
  const Rgb colour = scene.textures[static_cast<size_t>(m.reflectanceTexture)].lookup({0.25f, 0.5f});
  EXPECT_NEAR(colour.r, 1.0, 1e-6);
  EXPECT_NEAR(colour.g, srgbDecoded(128), 1e-6);
  EXPECT_NEAR(colour.b, 0.0, 1e-6);
  const Rgb data = scene.textures[static_cast<size_t>(m.metallicRoughnessTexture)].lookup({0.75f, 0.5f});
  EXPECT_NEAR(data.g, 64 / 255.0, 1e-6);
}

TEST(GltfRender, SamplerWrapModesReachTheTexture) {
  // The 2 x 1 image: texel 0 = (255, 128, 0), texel 1 = (64, 64, 64).
  const unsigned char pixels[] = {255, 128, 0, 64, 64, 64};
  std::filesystem::create_directories(renderFolder());
  ASSERT_NE(stbi_write_png((renderFolder() / "wrap.png").c_str(), 2, 1, 3, pixels, 6), 0);
  GltfBuilder b;
  b.doc()["images"] = {{{"uri", "wrap.png"}}};
  b.doc()["samplers"] = {{{"wrapS", 33071}, {"wrapT", 33648}}};  // CLAMP_TO_EDGE, MIRRORED_REPEAT
  b.doc()["textures"] = {{{"source", 0}, {"sampler", 0}}};
  b.doc()["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
  b.scene({b.node({{"mesh", b.square(0)}}), b.camera({0, 0, 3})});
  const Scene scene = loadScene(b.write(renderFolder(), "wrapped"));
  const ImageTexture& texture =
      scene.textures[static_cast<size_t>(scene.materials[static_cast<size_t>(scene.objects[0].material)].reflectanceTexture)];
  // u = 1.25 clamps to the right edge, texel 1; repeating it would read texel 0.
  EXPECT_NEAR(texture.lookup({1.25f, 0.5f}).r, srgbDecoded(64), 1e-6);
}

TEST(GltfRender, TextureTransformMovesTheUvsAsTheExtensionSays) {
  const unsigned char pixels[] = {255, 255, 255};
  std::filesystem::create_directories(renderFolder());
  ASSERT_NE(stbi_write_png((renderFolder() / "white.png").c_str(), 1, 1, 3, pixels, 3), 0);
  GltfBuilder b;
  b.doc()["images"] = {{{"uri", "white.png"}}};
  b.doc()["textures"] = {{{"source", 0}}};
  // Rotation by a quarter turn, scale 2, offset (0.5, 0.25): T * R * S maps glTF uv
  // (u, v) to (0.5 + 2 sin(r) v, 0.25 - 2 sin(r) u) with cos(r) = 0, sin(r) = 1.
  b.doc()["materials"] = {
      {{"pbrMetallicRoughness",
        {{"baseColorTexture",
          {{"index", 0},
           {"extensions",
            {{"KHR_texture_transform", {{"offset", {0.5, 0.25}}, {"rotation", M_PI / 2}, {"scale", {2, 2}}}}}}}}}}}};
  b.scene({b.node({{"mesh", b.square(0)}}), b.camera({0, 0, 3})});
  const Scene scene = loadScene(b.write(renderFolder(), "transformed"));
  const TriangleMesh& mesh = *scene.objects[0].mesh;
  // Vertex 1 has glTF uv (1, 1): transformed (2.5, -1.75), then v flipped: (2.5, 2.75).
  EXPECT_NEAR(mesh.uvs[1].x, 2.5f, 1e-5f);
  EXPECT_NEAR(mesh.uvs[1].y, 2.75f, 1e-5f);
  // Vertex 3 has glTF uv (0, 0): only the offset, (0.5, 0.25), flipped: (0.5, 0.75).
  EXPECT_NEAR(mesh.uvs[3].x, 0.5f, 1e-5f);
  EXPECT_NEAR(mesh.uvs[3].y, 0.75f, 1e-5f);
}

// A lamp square (emission 3, a black body the JSON scene makes Lambertian) filling the
// view's middle in front of a sky of radiance 1, with the given alpha mode.
FrameImage renderCutOut(const std::string& name, const nlohmann::json& material, bool rgbaTexture) {
  GltfBuilder b;
  nlohmann::json m = material;
  m["name"] = "lamp";
  m["emissiveFactor"] = {1, 1, 1};
  m["extensions"] = {{"KHR_materials_emissive_strength", {{"emissiveStrength", 3}}}};
  if (rgbaTexture) {
    // Left texel opaque, right texel fully transparent.
    const unsigned char pixels[] = {0, 0, 0, 255, 0, 0, 0, 0};
    std::filesystem::create_directories(renderFolder());
    EXPECT_NE(stbi_write_png((renderFolder() / "alpha.png").c_str(), 2, 1, 4, pixels, 8), 0);
    b.doc()["images"] = {{{"uri", "alpha.png"}}};
    b.doc()["textures"] = {{{"source", 0}}};
    m["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  }
  b.doc()["materials"] = {m};
  b.scene({b.node({{"mesh", b.square(0)}}), b.camera({0, 0, 4}, 2 * std::atan(0.5))});
  b.write(renderFolder(), name);
  const Scene scene = parseScene(R"({"include": ")" + name + R"(.gltf",
    "materials": {"lamp": {"type": "diffuse", "reflectance": 0}}, "environment": {"radiance": 1}})",
                                 renderFolder() / "shot.json");
  RenderSettings settings = RenderSettings::defaultsOf(scene);
  settings.width = settings.height = 40;
  settings.spp = 16;
  return FrameRenderer(scene, settings).render(0);
}

TEST(GltfRender, MaskCutsOutWhereTheTextureAlphaIsBelowTheCutoff) {
  const FrameImage image = renderCutOut("mask", {{"alphaMode", "MASK"}, {"alphaCutoff", 0.5}}, true);
  // The square spans x, y in [-1, 1]; its left half (u < 0.5) is there, its right half not.
  EXPECT_NEAR(meanOver(image, -0.8, -0.2, -0.8, 0.8), 3.0, 1e-4);
  EXPECT_NEAR(meanOver(image, 0.2, 0.8, -0.8, 0.8), 1.0, 1e-4);
}

TEST(GltfRender, BlendPassesRaysThroughInProportionToTransparency) {
  // Alpha 0.25 everywhere: a quarter of the rays stop at the lamp (3), the rest see the
  // sky (1); the mean is 1.5. Each pixel is a mean of 16 Bernoulli draws, so over about
  // 300 pixels the standard error is 2 * sqrt(0.25 * 0.75 / 4800) = 0.0125.
  const FrameImage image =
      renderCutOut("blend", {{"alphaMode", "BLEND"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 0.25}}}}},
                   false);
  EXPECT_NEAR(meanOver(image, -0.8, 0.8, -0.8, 0.8), 1.5, 5 * 0.0125);
}

// The lamp square of emission 3 at z = 0 before a sky of radiance 1, seen through a clear
// solid (KHR_materials_volume) sheet of index `ior` tilted 30 degrees between it and the
// camera, or without the sheet when `ior` is 0.
FrameImage renderThroughSheet(const std::string& name, double ior) {
  GltfBuilder b;
  b.doc()["materials"] = {{{"name", "lamp"}, {"emissiveFactor", {1, 1, 1}},
                           {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 3}}}}}},
                          {{"name", "sheet"},
                           {"pbrMetallicRoughness", {{"metallicFactor", 0}, {"roughnessFactor", 0}}},
                           {"extensions",
                            {{"KHR_materials_transmission", {{"transmissionFactor", 1}}},
                             {"KHR_materials_ior", {{"ior", ior > 0 ? ior : 1.5}}},
                             {"KHR_materials_volume", {{"thicknessFactor", 1}}}}}}};
  std::vector<int> nodes{b.node({{"mesh", b.square(0)}, {"scale", {0.6, 0.6, 1}}}), b.camera({0, 0, 4})};
  const float s = std::sin(kPi / 12), c = std::cos(kPi / 12);  // a 30-degree turn about y
  if (ior > 0) nodes.push_back(b.node({{"mesh", b.square(1)}, {"translation", {0, 0, 1.5}}, {"scale", {3, 3, 1}},
                                      {"rotation", {0, s, 0, c}}}));
  b.scene(nodes);
  b.write(renderFolder(), name);
  const Scene scene = parseScene(R"({"include": ")" + name + R"(.gltf",
    "materials": {"lamp": {"type": "diffuse", "reflectance": 0}}, "environment": {"radiance": 1}})",
                                 renderFolder() / (name + ".json"));
  RenderSettings settings = RenderSettings::defaultsOf(scene);
  settings.width = settings.height = 32;
  settings.spp = 4;
  return FrameRenderer(scene, settings).render(0);
}

TEST(GltfRender, AnIorOfOneNeitherReflectsNorBendsLight) {
  const auto difference = [](const FrameImage& a, const FrameImage& b) {
    double sum = 0;
    for (size_t i = 0; i < a.channel("G").size(); ++i) sum += std::abs(a.channel("G")[i] - b.channel("G")[i]);
    return sum / static_cast<double>(a.channel("G").size());
  };
  const FrameImage bare = renderThroughSheet("no_sheet", 0);
  EXPECT_LT(difference(renderThroughSheet("air_sheet", 1.0), bare), 1e-4);
  // Glass's index shifts the lamp and reflects the sky: the comparison can tell.
  EXPECT_GT(difference(renderThroughSheet("glass_sheet", 1.5), bare), 0.05);
}

}  // namespace
}  // namespace pathfarm
