// Emissive textures: a panel whose emissive texture is red on its left and green on its
// right half shows them where the camera sees it, and lights a floor as the integral of
// its textured radiance says, found here by quadrature over the panel, which checks that
// next-event estimation reads the texture where it samples the panel.
#include <gtest/gtest.h>
#include <stb_image_write.h>

#include <algorithm>
#include <cmath>

#include "renderer/integrators/frame_renderer.h"
#include "renderer/scene/scene_loader.h"
#include "test_support.h"
#include "tests/renderer/scene/gltf/gltf_builder.h"

namespace pathfarm {
namespace {

using gltftest::GltfBuilder;

std::filesystem::path emissionFolder() { return test_support::processTemporaryFolder("pathfarm_gltf_emission"); }

constexpr double kStrength = 5;

// The panel's red and green radiance at texture coordinate u: the 2 x 1 texture's texels
// (red, green; sRGB 255 and 0 decode to 1 and 0) at u = 1/4 and 3/4, blended linearly
// between them and clamped beyond (CLAMP_TO_EDGE).
double panelRed(double u) { return kStrength * std::clamp(1.5 - 2 * u, 0.0, 1.0); }
double panelGreen(double u) { return kStrength - panelRed(u); }

// The panel: the unit square scaled to 1 x 1, facing -z, at x in [1, 2], |y| <= 0.5,
// z = 1, u running along +x; with a floor (the unit square scaled 100) at z = 0.
GltfBuilder panelScene(bool withFloor) {
  const unsigned char texels[] = {255, 0, 0, 0, 255, 0};
  std::filesystem::create_directories(emissionFolder());
  EXPECT_NE(stbi_write_png((emissionFolder() / "two_texels.png").c_str(), 2, 1, 3, texels, 6), 0);
  GltfBuilder b;
  b.doc()["images"] = {{{"uri", "two_texels.png"}}};
  b.doc()["samplers"] = {{{"wrapS", 33071}, {"wrapT", 33071}}};
  b.doc()["textures"] = {{{"source", 0}, {"sampler", 0}}};
  b.doc()["extensionsUsed"] = {"KHR_materials_emissive_strength"};
  b.doc()["materials"] = {
      {{"name", "panel"},
       {"emissiveFactor", {1, 1, 1}},
       {"emissiveTexture", {{"index", 0}}},
       {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", kStrength}}}}}},
      {{"name", "floor"}}};
  std::vector<int> roots;
  // Turned half a turn about x to face -z: x stays, y flips.
  roots.push_back(b.node({{"mesh", b.square(0)},
                          {"translation", {1.5, 0, 1}},
                          {"rotation", {1, 0, 0, 0}},
                          {"scale", {0.5, 0.5, 1}}}));
  if (withFloor) roots.push_back(b.node({{"mesh", b.square(1)}, {"scale", {100, 100, 1}}}));
  b.scene(roots);
  return b;
}

TEST(GltfEmission, TheCameraSeesTheTextureOnThePanel) {
  GltfBuilder b = panelScene(false);
  b.write(emissionFolder(), "seen");
  // From 2 below the panel's centre, looking up at its emitting side; the view spans
  // 1 x 1 of it (a half-angle of atan 1/4).
  const Scene scene = parseScene(R"({"include": "seen.gltf",
    "camera": {"position": [1.5, 0, -1], "look_at": [1.5, 0, 1], "up": [0, 1, 0], "fov": 28.0724869},
    "render": {"resolution": [16, 16], "spp": 4}})", emissionFolder() / "seen.json");
  const FrameImage image = FrameRenderer(scene, RenderSettings::defaultsOf(scene)).render(0);
  // Looking up +z with +y up, +x is to the image's left. Pixel column px sees panel
  // x = 1.5 + 0.5 - (px + 0.5) / 16, so u = x - 1; pixel centres carry bilinear values
  // up to the pixel's own spread (1/16 in u, a change of 2 x 1/16 x 5 / 2 either way).
  const auto& red = image.channel("R");
  const auto& green = image.channel("G");
  for (int px = 0; px < 16; ++px) {
    const double u = 1 - (px + 0.5) / 16;
    const size_t p = 8 * 16 + static_cast<size_t>(px);
    EXPECT_NEAR(red[p], panelRed(u), 0.32) << "column " << px;
    EXPECT_NEAR(green[p], panelGreen(u), 0.32) << "column " << px;
  }
}

// The floor's radiance at (x, y, 0) from the panel, albedo / pi times the integral of
// L cos cos' / r^2 over it (the panel faces -z, so both cosines are 1 / r).
double floorRadiance(double x, double y, double (*panel)(double)) {
  const int n = 24;
  double sum = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double px = 1 + (i + 0.5) / n, py = -0.5 + (j + 0.5) / n;
      const double dx = px - x, dy = py - y;
      const double r2 = dx * dx + dy * dy + 1;
      sum += panel(px - 1) / (r2 * r2);
    }
  return 0.5 / 3.14159265358979323846 * sum / (n * n);
}

TEST(GltfEmission, TheTexturedPanelLightsTheFloorAsItsIntegralSays) {
  GltfBuilder b = panelScene(true);
  b.doc()["scenes"][0]["nodes"].push_back(b.camera({0, 0, 2}, 2 * std::atan(0.5)));
  b.write(emissionFolder(), "lit");
  const Scene scene = parseScene(R"({"include": "lit.gltf",
    "render": {"resolution": [16, 16], "spp": 32, "max_depth": 1},
    "materials": {"floor": {"type": "diffuse", "reflectance": 0.5}}})", emissionFolder() / "lit.json");
  const FrameImage image = FrameRenderer(scene, RenderSettings::defaultsOf(scene)).render(0);
  for (const auto& [channel, panel] : {std::pair{"R", &panelRed}, std::pair{"G", &panelGreen}}) {
    const auto estimate = test_support::meanOverPixels(image, channel);
    // The camera sees |x|, |y| <= 1 of the floor; the midpoint rule over it.
    const int n = 64;
    double reference = 0;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) reference += floorRadiance((i + 0.5) / n * 2 - 1, (j + 0.5) / n * 2 - 1, panel);
    reference /= n * n;
    EXPECT_NEAR(estimate.mean, reference, 4 * estimate.standardError + 1e-4) << channel;
  }
}

}  // namespace
}  // namespace pathfarm
