// Walks and their densities agree: for vertices y drawn by a walk, the mean of
// 1(y on a quad) / p(y) is the quad's area (p > 0 all over it), an estimate that needs
// nothing but the sampler and the density function being consistent.
#include "renderer/metropolis/path_space/path_walk.h"

#include <gtest/gtest.h>

#include <cmath>

#include "path_space_fixture.h"
#include "renderer/bidirectional/vertex_scattering.h"

namespace pathfarm {
namespace {

using test_support::WindowFixture;

// A 1 x 1 grey quad at z = 0 and, between it and the camera at z = 4, a 0.5 x 0.5 lamp at
// z = 2 facing the quad, which hides the quad from the camera exactly.
const char* kScene = R"({
  "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov": 40, "shutter": [0, 1]},
  "materials": {"grey": {"type": "diffuse", "reflectance": 0.5}, "lamp": {"type": "diffuse", "reflectance": 0}},
  "shapes": [
    {"type": "rectangle", "size": [1, 1], "material": "grey"},
    {"type": "rectangle", "size": [0.5, 0.5], "material": "lamp", "emission": 5,
     "transform": {"translate": [0, 0, 2], "rotate": {"axis": [1, 0, 0], "angle": 180}}}]
})";
constexpr int kQuad = 0, kLamp = 1;
constexpr int kSamples = 40000;

struct AreaEstimate {
  double mean = 0, standardError = 0;
};

// Mean and standard error of 1(on `object`) / density over kSamples draws.
template <class Draw>
AreaEstimate estimateArea(int object, const Draw& draw) {
  double sum = 0, sumSquares = 0;
  for (int i = 0; i < kSamples; ++i) {
    SampleStream random(SampleKey{3, 0, i, 0, 0});
    double density = 0;
    const std::optional<PathVertex> y = draw(random, density);
    const double value = y && y->type != VertexType::Environment && y->hit.object == object ? 1 / density : 0;
    sum += value;
    sumSquares += value * value;
  }
  const double mean = sum / kSamples;
  return {mean, std::sqrt((sumSquares / kSamples - mean * mean) / kSamples)};
}

void expectArea(const AreaEstimate& estimate, double area) {
  EXPECT_NEAR(estimate.mean, area, 4 * estimate.standardError + 1e-3 * area);
  EXPECT_LT(estimate.standardError, 0.05 * area);  // enough draws landed to test anything
}

class PathWalk : public ::testing::Test {
 protected:
  WindowFixture f{kScene, {0, 1}, 32, 4};
  BdptScene bdpt = f.window.frame(0);
  PathVertex camera, onQuad, onLamp;

  void SetUp() override {
    camera.type = VertexType::Camera;
    camera.hit.position = {0, 0, 4};
    camera.hit.geometricNormal = {0, 0, -1};
    ASSERT_TRUE(f.geometry.frame(0).intersect({{0.1f, 0.2f, 1}, {0, 0, -1}}, 0, onQuad.hit));
    ASSERT_TRUE(f.geometry.frame(0).intersect({{0.1f, 0.1f, 1}, {0, 0, 1}}, 0, onLamp.hit));
    onLamp.type = VertexType::Light;
  }

  // The area estimate of `object` from walks leaving `start`, reached from `before`.
  AreaEstimate walks(int object, const PathVertex* before, const PathVertex& start) const {
    return estimateArea(object, [&](SampleStream& random, double& density) {
      PathVertex from = start;
      auto y = walkFrom(bdpt, 0, before, from, random);
      if (y) density = walkDensity(bdpt, 0, before, from, *y);
      return y;
    });
  }
};

TEST_F(PathWalk, FromTheCamera) { expectArea(walks(kLamp, nullptr, camera), 0.25); }

TEST_F(PathWalk, FromADiffuseSurfaceTowardsTheLamp) { expectArea(walks(kLamp, &camera, onQuad), 0.25); }

TEST_F(PathWalk, FromALightEnd) { expectArea(walks(kQuad, nullptr, onLamp), 1.0); }

TEST_F(PathWalk, NewLightEnds) {
  expectArea(estimateArea(kLamp, [&](SampleStream& random, double& density) {
               auto y = sampleLightEnd(bdpt, 0, random);
               if (y) density = lightStartDensity(bdpt, 0, *y);
               return y;
             }),
             0.25);
}

}  // namespace
}  // namespace pathfarm
