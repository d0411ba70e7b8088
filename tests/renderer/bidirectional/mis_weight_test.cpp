// Multiple importance sampling of bidirectional strategies: the weights of all
// strategies of one path sum to 1, and the densities the subpaths record agree with the
// densities evaluated from the complete path alone.
#include "renderer/bidirectional/mis_weight.h"

#include <gtest/gtest.h>

#include "bdpt_fixture.h"
#include "renderer/bidirectional/complete_path.h"
#include "renderer/bidirectional/connection.h"
#include "renderer/bidirectional/subpath.h"

namespace pathfarm {
namespace {

bool hasDeltaVertex(const CompletePath& path) {
  for (const PathVertex& v : path.vertices)
    if (v.delta) return true;
  return false;
}

// Every strategy's complete path from `samples` pairs of camera and light subpaths on the
// Cornell box at 24x24, sample i through pixel (i % 24, i / 24 % 24):
// visit(fixture, bdpt, path, sample, s, t).
template <class Visit>
void forEachStrategyPath(uint32_t samples, const Visit& visit) {
  const test_support::BdptFixture fixture(loadScene(test_support::sourceDir() / "scenes/cornell/scene.json"), 24, 24,
                                          3);
  const BdptScene bdpt = fixture.bdpt(5);
  Subpath camera, light;
  for (uint32_t i = 0; i < samples; ++i) {
    SampleStream stream({7, 3, static_cast<int32_t>(i % 24), static_cast<int32_t>(i / 24 % 24), i});
    StreamSource u(stream);
    const Vec2f jitter = u.next2D();
    const Vec2f film{jitter.x * 24, jitter.y * 24};
    const float time = u.next1D();
    generateCameraSubpath(bdpt, time, film, u.next2D(), u, maxCameraVertices(bdpt), camera);
    generateLightSubpath(bdpt, time, u, maxLightVertices(bdpt), light);
    forEachStrategy(bdpt, camera, light, [&](int s, int t) {
      CompletePath path;
      path.time = time;
      const auto sample = connectStrategy(bdpt, time, camera, light, s, t, u, &path.vertices);
      if (sample) visit(fixture, bdpt, path, *sample, s, t);
    });
  }
}

TEST(BdptMisWeights, StrategiesOfEveryPathSumToOneAndMatchTheSubpathDensities) {
  int checkedContributions = 0;
  forEachStrategyPath(300, [&](const test_support::BdptFixture& fixture, const BdptScene& bdpt, CompletePath& path,
                               const auto& sample, int s, int t) {
    const PathDensities d = densitiesOf(bdpt, path);
    double sum = 0;
    for (int other = 1; other <= path.length() + 1; ++other) sum += misWeight(d, other);
    EXPECT_NEAR(sum, 1.0, 1e-5) << "s=" << s << " t=" << t;
    EXPECT_NEAR(sample.misWeight, misWeight(d, t), 1e-5) << "s=" << s << " t=" << t;
    if (hasDeltaVertex(path)) return;
    // f / p of the strategy against f and p evaluated from the vertices alone. Subpaths
    // follow their sampled directions, which differ from those between the stored
    // (offset-free) positions by rounding, amplified at grazing angles: 1 %.
    const double f = measure(bdpt, path).f[1];
    const double p = strategyDensity(d, t) * fixture.camera.lensDensity();
    EXPECT_NEAR(sample.unweighted[1], f / p, 1e-2 * f / p) << "s=" << s << " t=" << t;
    ++checkedContributions;
  });
  EXPECT_GT(checkedContributions, 500);
}

// A path whose vertex is repeated has an edge of zero length: it carries nothing, and
// its measurement stays finite (a NaN direction reached the BSDFs before).
TEST(BdptMeasurement, AnEdgeOfZeroLengthCarriesNothing) {
  int degenerate = 0;
  forEachStrategyPath(50, [&](const test_support::BdptFixture&, const BdptScene& bdpt, CompletePath& path,
                              const auto&, int s, int t) {
    if (path.length() < 2 || measure(bdpt, path).f.isBlack()) return;
    path.vertices.insert(path.vertices.begin() + 1, path.vertices[1]);
    const PathMeasurement m = measure(bdpt, path);
    EXPECT_TRUE(m.f.isBlack() && m.f.isFinite()) << "s=" << s << " t=" << t;
    ++degenerate;
  });
  EXPECT_GE(degenerate, 20);
}

}  // namespace
}  // namespace pathfarm
