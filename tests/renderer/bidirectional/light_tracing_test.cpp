// Light subpaths on their own: emitter points are chosen in proportion to power with the
// density they report, and light tracing alone (t = 1, no MIS) renders what the path
// tracer renders.
#include <gtest/gtest.h>

#include "bdpt_fixture.h"
#include "renderer/bidirectional/connection.h"
#include "renderer/bidirectional/subpath.h"
#include "renderer/integrators/frame_renderer.h"

namespace pathfarm {
namespace {

TEST(EmitterSampling, DensitiesIntegrateToTheEmittersAreaAndPower) {
  const test_support::BdptFixture fixture(test_support::sceneFromJson(R"({
    "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]},
    "materials": {"lamp": {"type": "diffuse", "reflectance": 0.5}},
    "shapes": [
      {"name": "panel", "type": "rectangle", "size": [1, 0.5], "material": "lamp", "emission": [2, 2, 2],
       "transform": {"translate": [-1, 0, 0]}},
      {"name": "bulb", "type": "sphere", "radius": 0.25, "material": "lamp", "emission": [1, 1, 1],
       "transform": {"translate": [1, 0, 0]}}]
  })"),
                                          8, 8);
  const double panelArea = 0.5, bulbArea = 4 * kPi * 0.25 * 0.25;
  const double panelPower = kPi * 2 * panelArea, bulbPower = kPi * 1 * bulbArea;
  const int n = 200000;
  double inverseDensity = 0, inverseDensitySquared = 0, power = 0;
  int panel = 0;
  for (int i = 0; i < n; ++i) {
    SampleStream stream({3, 0, i, 0, 0});
    const auto point = fixture.lights.sampleEmitterPoint(fixture.frame, 0.5f, stream.next1D(), stream.next2D());
    ASSERT_TRUE(point.has_value());
    EXPECT_FLOAT_EQ(fixture.lights.emitterPointPdf(fixture.frame, point->hit, 0.5f), point->pdfArea);
    inverseDensity += 1 / point->pdfArea;
    inverseDensitySquared += 1 / (double(point->pdfArea) * point->pdfArea);
    power += kPi * point->radiance.luminance() / point->pdfArea;
    panel += point->hit.object == 0;
  }
  const double meanArea = inverseDensity / n;
  const double areaError = std::sqrt((inverseDensitySquared / n - meanArea * meanArea) / n);
  EXPECT_NEAR(meanArea, panelArea + bulbArea, 4 * areaError + 1e-4);
  // Power-proportional choice makes Le pi / p(y) the total power for every sample.
  EXPECT_NEAR(power / n, panelPower + bulbPower, 1e-3 * (panelPower + bulbPower));
  const double share = panelPower / (panelPower + bulbPower);
  EXPECT_NEAR(double(panel) / n, share, 4 * std::sqrt(share * (1 - share) / n));
}

// The Cornell box without its mirror and glass spheres: every surface is diffuse.
Scene diffuseCornellBox() {
  Scene scene = loadScene(test_support::sourceDir() / "scenes/cornell/scene.json");
  std::erase_if(scene.objects, [](const SceneObject& o) { return o.name == "mirror_sphere" || o.name == "glass_sphere"; });
  return scene;
}

TEST(LightTracing, AloneAgreesWithThePathTracerOnADiffuseScene) {
  const int size = 16, maxDepth = 4;
  test_support::BdptFixture fixture(diffuseCornellBox(), size, size);
  RenderSettings settings;
  settings.width = settings.height = size;
  settings.spp = 256;
  settings.maxDepth = maxDepth;
  const FrameImage pt = FrameRenderer(fixture.scene, settings).render(0);

  // Per quadrant of the image: the mean pixel value by light tracing, with its standard
  // error from the spread of the light paths' contributions.
  const BdptScene bdpt = fixture.bdpt(maxDepth);
  const int paths = 60000;
  double sum[4] = {}, sumSquares[4] = {};
  Subpath camera, light;
  for (int i = 0; i < paths; ++i) {
    SampleStream stream({11, 0, i, 0, 0});
    StreamSource u(stream);
    const float time = u.next1D();
    generateCameraSubpath(bdpt, time, {0, 0}, {0.5f, 0.5f}, u, 1, camera);  // the lens alone
    generateLightSubpath(bdpt, time, u, maxLightVertices(bdpt), light);
    double perQuadrant[4] = {};
    for (int s = 1; s <= static_cast<int>(light.size()); ++s) {
      const auto sample = connectStrategy(bdpt, time, camera, light, s, 1, u);
      if (!sample) continue;
      const int quadrant = (sample->raster.x >= size / 2 ? 1 : 0) + (sample->raster.y >= size / 2 ? 2 : 0);
      // Pixel values are W H times the expectation (connection.h); a quadrant's mean
      // pixel is that over its W H / 4 pixels.
      perQuadrant[quadrant] += sample->unweighted.luminance() * 4;
    }
    for (int q = 0; q < 4; ++q) {
      sum[q] += perQuadrant[q];
      sumSquares[q] += perQuadrant[q] * perQuadrant[q];
    }
  }
  for (int q = 0; q < 4; ++q) {
    const double lightTraced = sum[q] / paths;
    const double lightError = std::sqrt((sumSquares[q] / paths - lightTraced * lightTraced) / paths);
    double pathTraced = 0, ptVariance = 0;
    const int count = size * size / 4;
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        if ((x >= size / 2 ? 1 : 0) + (y >= size / 2 ? 2 : 0) != q) continue;
        const size_t p = static_cast<size_t>(y * size + x);
        const Rgb value{pt.channel("R")[p], pt.channel("G")[p], pt.channel("B")[p]};
        const Rgb variance{pt.channel("variance.R")[p], pt.channel("variance.G")[p], pt.channel("variance.B")[p]};
        pathTraced += value.luminance() / count;
        // A conservative bound on the luminance's variance (channels fully correlated).
        const double spread = 0.2126 * std::sqrt(variance.r) + 0.7152 * std::sqrt(variance.g) +
                              0.0722 * std::sqrt(variance.b);
        ptVariance += spread * spread / (double(count) * count);
      }
    EXPECT_NEAR(lightTraced, pathTraced, 4.5 * std::sqrt(lightError * lightError + ptVariance)) << "quadrant " << q;
    EXPECT_GT(pathTraced, 0.01);
  }
}

}  // namespace
}  // namespace pathfarm
