// Specular chains: re-tracing regenerates the path it came from, and the regeneration
// densities of the two ways are consistent with the geometry: the Jacobian of the map
// (x_a, x_a+1) -> (x_b-1, x_b) that a chain defines, measured by finite differences,
// equals R_light / R_cam (specular_chain.h), for mirrors and for refraction.
#include "renderer/metropolis/path_space/specular_chain.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "path_space_fixture.h"
#include "renderer/math/frame.h"
#include "toy_scenes.h"

namespace pathfarm {
namespace {

using test_support::WindowFixture;

// |det| of a 4 x 4 matrix by Gaussian elimination with partial pivoting.
double absDeterminant(std::array<std::array<double, 4>, 4> m) {
  double det = 1;
  for (int c = 0; c < 4; ++c) {
    int pivot = c;
    for (int r = c + 1; r < 4; ++r)
      if (std::abs(m[r][c]) > std::abs(m[pivot][c])) pivot = r;
    std::swap(m[c], m[pivot]);
    det *= m[c][c];
    if (m[c][c] == 0) return 0;
    for (int r = c + 1; r < 4; ++r) {
      const double f = m[r][c] / m[c][c];
      for (int k = c; k < 4; ++k) m[r][k] -= f * m[c][k];
    }
  }
  return std::abs(det);
}

// The chains of sampled paths whose ends are both surfaces (so that both can move).
struct ChainCase {
  PathSpaceState state;
  SpecularChain chain;
};

std::vector<ChainCase> surfaceChains(const WindowFixture& f, int samples) {
  std::vector<ChainCase> cases;
  for (PathSpaceState& s : f.samplePaths(samples, 11))
    for (const SpecularChain& c : specularChainsOf(s.path.vertices))
      if (s.path.vertices[static_cast<size_t>(c.a)].isSurfaceLike() &&
          s.path.vertices[static_cast<size_t>(c.b)].isSurfaceLike())
        cases.push_back({s, c});
  return cases;
}

// Checks the Jacobian of the chain map against the densities for up to `wanted` chains;
// returns how many were checked.
int checkJacobians(const WindowFixture& f, const std::vector<ChainCase>& cases, int wanted) {
  int checked = 0;
  for (const ChainCase& c : cases) {
    if (checked == wanted) break;
    const std::vector<PathVertex>& x = c.state.path.vertices;
    const auto at = [](int i) { return static_cast<size_t>(i); };
    const WindowInstant instant = *f.time.instant(c.state.tau);
    const BdptScene bdpt = f.window.frame(instant.frame);
    const int a = c.chain.a, b = c.chain.b;
    // Tangent frames of the four vertices involved; a perturbed vertex is put back on its
    // (possibly curved) surface along the normal, with the normal found there.
    const int in[2] = {a, a + 1}, out[2] = {b - 1, b};
    const auto tangent = [&](int i, int axis) {
      const Frame frame = Frame::fromNormal(x[at(i)].hit.geometricNormal);
      return axis == 0 ? frame.s : frame.t;
    };
    const double h = 2e-4;
    std::array<std::array<double, 4>, 4> jacobian{};
    bool traced = true;
    for (int column = 0; column < 4 && traced; ++column) {
      Vec3f ends[2][2];
      for (int sign = 0; sign < 2 && traced; ++sign) {
        std::vector<PathVertex> moved = x;
        PathVertex& v = moved[at(in[column / 2])];
        const Vec3f n = v.hit.geometricNormal;
        const Vec3f shifted = v.hit.position + tangent(in[column / 2], column % 2) * static_cast<float>(sign ? h : -h);
        SurfaceHit onSurface;
        if (!bdpt.geometry.intersect({shifted + n * 0.01f, -n}, instant.shutterFraction, onSurface)) onSurface = v.hit;
        if (onSurface.object != v.hit.object) traced = false;
        v.hit = onSurface;
        traced = traced && retraceChain(bdpt, instant.shutterFraction, x, c.chain, ChainDirection::FromCamera, moved);
        ends[sign][0] = moved[at(out[0])].position();
        ends[sign][1] = moved[at(out[1])].position();
      }
      for (int row = 0; row < 4 && traced; ++row) {
        const Vec3f d = ends[1][row / 2] - ends[0][row / 2];
        jacobian[static_cast<size_t>(row)][static_cast<size_t>(column)] = dot(d, tangent(out[row / 2], row % 2)) / (2 * h);
      }
    }
    if (!traced) continue;  // a perturbed ray left the chain's surfaces
    const Scene& scene = f.scene;
    const double expected = regenerationDensity(scene, x, c.chain, ChainDirection::FromLight) /
                            regenerationDensity(scene, x, c.chain, ChainDirection::FromCamera);
    EXPECT_NEAR(absDeterminant(jacobian) / expected, 1, 2e-2) << "chain " << a << ".." << b;
    ++checked;
  }
  return checked;
}

TEST(SpecularChain, RetracingAChainGivesTheSamePath) {
  const WindowFixture f(test_support::movingMirrorScene(), {0, 4}, 16, 4);
  int checked = 0;
  for (const PathSpaceState& s : f.samplePaths(400, 3)) {
    const WindowInstant instant = *f.time.instant(s.tau);
    const BdptScene bdpt = f.window.frame(instant.frame);
    for (const SpecularChain& c : specularChainsOf(s.path.vertices))
      for (const ChainDirection way : {ChainDirection::FromCamera, ChainDirection::FromLight}) {
        std::vector<PathVertex> x = s.path.vertices;
        const bool anchoredOnLens = way == ChainDirection::FromLight && c.a == 0;
        ASSERT_EQ(retraceChain(bdpt, instant.shutterFraction, s.path.vertices, c, way, x), !anchoredOnLens);
        if (anchoredOnLens) continue;
        for (size_t i = 0; i < x.size(); ++i) test_support::expectNear(x[i].position(), s.path.vertices[i].position(), 1e-4f);
        ++checked;
      }
  }
  EXPECT_GT(checked, 10);
}

TEST(SpecularChain, MirrorChainDensitiesMatchTheJacobianOfTheChain) {
  const WindowFixture f(test_support::movingMirrorScene(), {0, 4}, 16, 4);
  EXPECT_GE(checkJacobians(f, surfaceChains(f, 3000), 20), 5);
}

TEST(SpecularChain, RefractionChainDensitiesMatchTheJacobianOfTheChain) {
  // A wedge: light enters and leaves by faces that are not parallel, where a slab (or a
  // ball's symmetric chords) would make the light side's density the mirror rule's.
  const WindowFixture f(test_support::glassWedgeScene(), {0, 4}, 16, 5);
  EXPECT_GE(checkJacobians(f, surfaceChains(f, 3000), 20), 5);
}

}  // namespace
}  // namespace pathfarm
