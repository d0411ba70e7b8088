// Detailed balance of the lens and caustic perturbations on the toy scenes (a moving
// mirror, a glass wedge), with the reverse move computed on its own (detailed_balance.h).
#include <gtest/gtest.h>

#include "detailed_balance.h"
#include "path_space_fixture.h"
#include "renderer/bidirectional/vertex_scattering.h"
#include "renderer/math/frame.h"
#include "renderer/metropolis/path_space/caustic_perturbation.h"
#include "renderer/metropolis/path_space/lens_perturbation.h"
#include "toy_scenes.h"

namespace pathfarm {
namespace {

using test_support::WindowFixture;

struct Counts {
  int checked = 0, throughChains = 0;
};

Counts checkLens(const WindowFixture& f) {
  Counts counts;
  for (const PathSpaceState& x : f.samplePaths(600, 8)) {
    for (const Vec2f offset : {Vec2f{0.3f, -0.2f}, Vec2f{-1.1f, 0.6f}}) {
      const PathMutation there = lensPerturbation(f.window, x, offset);
      const Vec2f home{x.contribution.film.x - there.proposed.contribution.film.x,
                       x.contribution.film.y - there.proposed.contribution.film.y};
      const PathMutation back = lensPerturbation(f.window, there.proposed, home);
      if (!test_support::expectDetailedBalance(x, there, back)) continue;
      ++counts.checked;
      counts.throughChains += x.path.vertices[1].delta;
    }
  }
  return counts;
}

Counts checkCaustic(const WindowFixture& f) {
  Counts counts;
  for (const PathSpaceState& x : f.samplePaths(1500, 9)) {
    const int j = causticSource(x.path.vertices);
    if (j < 0) continue;
    const auto& v = x.path.vertices;
    const Vec3f original = directionBetween(v[static_cast<size_t>(j)], v[static_cast<size_t>(j - 1)]);
    const Frame around = Frame::fromNormal(original);
    const Vec3f turned = normalize(around.toWorld({0.004f, -0.003f, 1}));
    const PathMutation there = causticPerturbation(f.window, x, turned);
    const PathMutation back = causticPerturbation(f.window, there.proposed, original);
    if (!test_support::expectDetailedBalance(x, there, back)) continue;
    ++counts.checked;
    counts.throughChains += j >= 3;
  }
  return counts;
}

// Both toy scenes: enough pairs checked, some of them through specular chains.
void expectBalancedOnToyScenes(Counts (*check)(const WindowFixture&)) {
  for (const std::string& scene : {test_support::movingMirrorScene(), test_support::glassWedgeScene()}) {
    const WindowFixture f(scene, {0, 4}, 16, 5);
    const Counts counts = check(f);
    EXPECT_GT(counts.checked, 100);
    EXPECT_GT(counts.throughChains, 5);
  }
}

TEST(LensPerturbation, DetailedBalanceThroughMirrorsAndGlass) { expectBalancedOnToyScenes(checkLens); }

// Veach's lens subpath is E S* D (D|L): the moved first non-delta vertex x_c cannot be
// reconnected to a delta x_c+1, whose Dirac directions it would break. Such a move once
// went through, f passing the lobe test's tolerance, and trapped chains in a band of
// paths no other sampler makes (glass_egg frame 3, E S S S D S S S D L).
TEST(LensPerturbation, DoesNotReconnectToADeltaVertex) {
  for (const std::string& scene : {test_support::movingMirrorScene(), test_support::glassWedgeScene()}) {
    const WindowFixture f(scene, {0, 4}, 16, 5);
    int applicable = 0, proposed = 0;
    for (const PathSpaceState& x : f.samplePaths(600, 8)) {
      const auto& v = x.path.vertices;
      size_t c = 1;
      while (v[c].delta) ++c;
      if (c + 1 >= v.size() || !v[c + 1].delta) continue;
      ++applicable;
      for (const Vec2f offset : {Vec2f{0.1f, 0}, Vec2f{0, -0.1f}, Vec2f{0.07f, 0.07f}})
        proposed += lensPerturbation(f.window, x, offset).proposed.density > 0;
    }
    EXPECT_GT(applicable, 20);
    EXPECT_EQ(proposed, 0);
  }
}

TEST(CausticPerturbation, DetailedBalanceThroughMirrorsAndGlass) { expectBalancedOnToyScenes(checkCaustic); }

TEST(CausticPerturbation, PathsWithoutASourceAreNotPerturbed) {
  PathVertex camera, mirror, lamp;
  camera.type = VertexType::Camera;
  mirror.delta = true;
  lamp.type = VertexType::Light;
  EXPECT_EQ(causticSource({camera, mirror, lamp}), -1);  // x1 delta
  PathVertex wall;
  EXPECT_EQ(causticSource({camera, wall, lamp}), 2);
  EXPECT_EQ(causticSource({camera, wall, mirror, mirror, lamp}), 4);
}

}  // namespace
}  // namespace pathfarm
