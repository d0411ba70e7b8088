// The bidirectional mutation's transition density, checked against an independent
// integral: the mutation that deletes everything after the camera (and renews the time)
// proposes Y with density T(X -> Y), so the mean over its proposals of f(Y) / T(X -> Y)
// estimates the integral of f over the paths it can reach (here: those of the length
// it keeps) and the open time, which bidirectional path tracing estimates on its own.
// Detailed balance of the mutation itself holds by construction (T both ways from one
// formula); this checks that the formula is the density the sampler draws from.
#include "renderer/metropolis/path_space/bidirectional_mutation.h"

#include <gtest/gtest.h>

#include <cmath>

#include "path_space_fixture.h"
#include "toy_scenes.h"

namespace pathfarm {
namespace {

using test_support::WindowFixture;

struct Estimate {
  double mean = 0, standardError = 0;
  void add(double v) {
    sum += v;
    sumSquares += v * v;
    ++n;
  }
  void finish(double count) {
    mean = sum / count;
    standardError = std::sqrt(std::max(0.0, sumSquares / count - mean * mean) / count);
  }
  double sum = 0, sumSquares = 0;
  int n = 0;
};

// Whether y keeps none of x's vertices but the camera: made by the whole-path mutation.
bool onlyCameraKept(const PathSpaceState& x, const PathSpaceState& y) {
  for (size_t i = 1; i < x.path.vertices.size(); ++i)
    for (size_t j = 1; j < y.path.vertices.size(); ++j)
      if (x.path.vertices[i].type == y.path.vertices[j].type &&
          x.path.vertices[i].position() == y.path.vertices[j].position() &&
          x.path.vertices[i].direction == y.path.vertices[j].direction)
        return false;
  return true;
}

void expectIntegralOfLength(const std::string& json, int length) {
  const WindowFixture f(json, {0, 2}, 16, 4);
  const int samples = 20000;
  std::vector<double> weights;
  const std::vector<PathSpaceState> paths = f.samplePaths(samples, 21, &weights);
  Estimate reference;
  for (size_t i = 0; i < paths.size(); ++i)
    if (paths[i].path.length() == length) reference.add(weights[i]);
  reference.finish(samples);
  // The mean over the open time: the mutation's estimate integrates over it.
  reference.mean *= f.time.openLength();
  reference.standardError *= f.time.openLength();

  const PathSpaceState* x = nullptr;
  for (const PathSpaceState& p : paths)
    if (p.path.length() == length) x = &p;
  ASSERT_NE(x, nullptr);
  const int proposals = 240000;
  Estimate mutated;
  for (int i = 0; i < proposals; ++i) {
    SampleStream random(SampleKey{77, 0, i, 0, 0});
    const PathMutation m = bidirectionalMutation(f.window, *x, random);
    if (m.proposed.density > 0 && m.proposed.path.length() == length && onlyCameraKept(*x, m.proposed))
      mutated.add(m.proposed.density / m.forward);
    else
      mutated.add(0);
  }
  mutated.finish(proposals);
  const double tolerance = 4 * std::hypot(reference.standardError, mutated.standardError);
  EXPECT_NEAR(mutated.mean, reference.mean, tolerance);
  EXPECT_LT(tolerance, 0.3 * reference.mean);  // a test that can tell
}

TEST(BidirectionalMutation, WholePathDensityIntegratesFOfOneLength) {
  expectIntegralOfLength(test_support::movingMirrorScene(), 2);
  expectIntegralOfLength(test_support::movingMirrorScene(), 3);
}

}  // namespace
}  // namespace pathfarm
