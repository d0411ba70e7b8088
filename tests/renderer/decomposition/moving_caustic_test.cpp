// The moving caustic of a decomposed render (moving_caustic.Y): light reaching the path's
// last diffuse vertex through a specular chain that touches an animated object. Checked
// against an independent split of the same samples: the light-path expression
// E.*D(R|T)+ of the decomposition's automaton takes exactly the caustic paths, so with
// every specular object animated the two agree pixel by pixel, and with none, the buffer
// is empty while the expression is not.
#include <gtest/gtest.h>

#include <string>

#include "renderer/integrators/frame_renderer.h"
#include "test_support.h"

namespace pathfarm {
namespace {

constexpr int kWidth = 32, kHeight = 24;

// A floor, a small bright lamp above, a glass ball and a mirror ball on the floor; each
// ball slides when asked to.
Scene causticScene(bool glassMoves, bool mirrorMoves) {
  const auto ball = [](const char* material, float x, bool moves) {
    const std::string at = "[" + std::to_string(x) + ", 0.35, 0]";
    const std::string later = "[" + std::to_string(x + 0.2f) + ", 0.35, 0]";
    return std::string(R"({"type": "sphere", "radius": 0.35, "material": ")") + material + "\", " +
           (moves ? R"("animation": {"translate": [{"frame": 0, "value": )" + at + R"(}, {"frame": 4, "value": )" +
                        later + "}]}}"
                  : R"("transform": {"translate": )" + at + "}}");
  };
  return test_support::sceneFromJson(R"({
    "camera": {"position": [0, 2.2, 2.6], "look_at": [0, 0.1, 0], "fov": 45},
    "materials": {"floor": {"type": "diffuse", "reflectance": 0.6},
                  "lamp": {"type": "diffuse", "reflectance": 0},
                  "mirror": {"type": "conductor", "specular_color": 0.95},
                  "glass": {"type": "dielectric", "ior": 1.5}},
    "shapes": [
      {"type": "rectangle", "size": [6, 6], "material": "floor", "transform": {"rotate": {"axis": [1, 0, 0], "angle": -90}}},
      {"type": "rectangle", "size": [0.5, 0.5], "material": "lamp", "emission": [60, 60, 60],
       "transform": {"translate": [0, 2.5, 0], "rotate": {"axis": [1, 0, 0], "angle": 90}}},
      )" + ball("glass", 0.4f, glassMoves) + ",\n" + ball("mirror", -0.5f, mirrorMoves) + R"(]
  })");
}

FrameImage renderWithCausticComponent(const Scene& scene) {
  RenderSettings settings;
  settings.width = kWidth;
  settings.height = kHeight;
  settings.spp = 64;
  settings.maxDepth = 8;
  settings.decomposition = std::make_shared<Decomposition>(Decomposition::parse("caustic=E.*D(R|T)+"));
  return FrameRenderer(scene, settings).render(1);
}

double luminanceOf(const FrameImage& image, const std::string& prefix, size_t p) {
  return 0.2126 * image.channel(prefix + "R")[p] + 0.7152 * image.channel(prefix + "G")[p] +
         0.0722 * image.channel(prefix + "B")[p];
}

double sumOf(const std::vector<float>& values) {
  double sum = 0;
  for (float v : values) sum += v;
  return sum;
}

TEST(MovingCaustic, WithEverySpecularObjectAnimatedItIsTheCausticExpressionPixelByPixel) {
  const FrameImage image = renderWithCausticComponent(causticScene(true, true));
  const std::vector<float>& moving = image.channel("moving_caustic.Y");
  double total = 0;
  for (size_t p = 0; p < moving.size(); ++p) {
    const double expected = luminanceOf(image, "caustic.color.", p);
    ASSERT_NEAR(moving[p], expected, 1e-4 * expected + 1e-6) << "pixel " << p;
    total += expected;
  }
  EXPECT_GT(total, 0.0) << "the glass ball focuses the lamp onto the floor";
}

TEST(MovingCaustic, StillMirrorsAndGlassMakeNone) {
  const FrameImage image = renderWithCausticComponent(causticScene(false, false));
  EXPECT_EQ(sumOf(image.channel("moving_caustic.Y")), 0.0);
  EXPECT_GT(sumOf(image.channel("caustic.color.G")), 0.0);
}

TEST(MovingCaustic, OnlyTheLightThroughTheMovingObjectCounts) {
  // The glass moves, the mirror does not: the glass's caustic is in the buffer, the
  // mirror's is not, so the buffer holds part of the caustic expression's light.
  const FrameImage image = renderWithCausticComponent(causticScene(true, false));
  const std::vector<float>& moving = image.channel("moving_caustic.Y");
  double movingTotal = 0, causticTotal = 0;
  for (size_t p = 0; p < moving.size(); ++p) {
    const double caustic = luminanceOf(image, "caustic.color.", p);
    ASSERT_LE(moving[p], caustic * (1 + 1e-4) + 1e-6) << "pixel " << p;
    movingTotal += moving[p];
    causticTotal += caustic;
  }
  EXPECT_GT(movingTotal, 0.0);
  EXPECT_LT(movingTotal, causticTotal);
}

}  // namespace
}  // namespace pathfarm
