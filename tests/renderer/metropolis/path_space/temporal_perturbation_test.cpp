// The temporal perturbation on toy scenes (a moving mirror, a moving glass wedge, a
// moving quad, a moving camera): detailed balance in both directions, with the reverse
// density T(Y -> X) computed by actually running the move back from Y, not by the
// forward move's formula; the move is its own inverse; vertices follow their objects.
#include "renderer/metropolis/path_space/temporal_perturbation.h"

#include <gtest/gtest.h>

#include <cmath>

#include "detailed_balance.h"
#include "path_space_fixture.h"
#include "renderer/metropolis/path_space/vertex_motion.h"
#include "toy_scenes.h"

namespace pathfarm {
namespace {

using test_support::WindowFixture;

struct BalanceCounts {
  int checked = 0, retraced = 0;
};

// For every sampled path and a few proposed times, both ways first: the move X -> Y and
// the move Y -> X it must be undone by.
BalanceCounts checkDetailedBalance(const WindowFixture& f, int samples) {
  const TemporalProposal proposal(f.time, 1.0);
  BalanceCounts counts;
  uint32_t n = 0;
  for (const PathSpaceState& x : f.samplePaths(samples, 5)) {
    for (int j = 0; j < 4; ++j, ++n) {
      const double tauNext = proposal.sample(x.tau, test_support::hashed(9, 0, static_cast<int>(n), j));
      const ChainDirection first = j % 2 ? ChainDirection::FromLight : ChainDirection::FromCamera;
      const TemporalMove there = temporalMove(f.window, proposal, x, tauNext, first);
      const TemporalMove back = temporalMove(f.window, proposal, there.mutation.proposed, x.tau, there.way);
      if (!test_support::expectDetailedBalance(x, there.mutation, back.mutation)) continue;
      EXPECT_EQ(back.way, there.way);
      ++counts.checked;
      counts.retraced += there.retraced;
    }
  }
  return counts;
}

TEST(TemporalPerturbation, DetailedBalanceWithAMovingMirror) {
  const WindowFixture f(test_support::movingMirrorScene(), {0, 4}, 16, 4);
  const BalanceCounts counts = checkDetailedBalance(f, 600);
  EXPECT_GT(counts.checked, 200);
  EXPECT_GT(counts.retraced, 20);
}

TEST(TemporalPerturbation, DetailedBalanceWithAMovingGlassWedge) {
  const WindowFixture f(test_support::glassWedgeScene(), {0, 4}, 16, 5);
  const BalanceCounts counts = checkDetailedBalance(f, 600);
  EXPECT_GT(counts.checked, 200);
  EXPECT_GT(counts.retraced, 20);
}

TEST(TemporalPerturbation, ClosedShutterIsRejected) {
  const WindowFixture f(test_support::movingMirrorScene(), {0, 4}, 16, 4);
  const TemporalProposal proposal(f.time, 1.0);
  const auto paths = f.samplePaths(50, 2);
  ASSERT_FALSE(paths.empty());
  const TemporalMove move = temporalMove(f.window, proposal, paths.front(), std::floor(paths.front().tau) + 0.75,
                                         ChainDirection::FromCamera);
  EXPECT_EQ(move.mutation.proposed.density, 0);
  EXPECT_EQ(move.mutation.forward, 0);
}

TEST(TemporalPerturbation, VerticesFollowTheirObjectsAndTheCamera) {
  const WindowFixture f(test_support::movingMirrorScene(), {0, 4}, 16, 4);
  // One frame later, at the same shutter fraction, the mirror and the quad have moved by a
  // quarter of their translation (0.4, 0.2, 0.3), the camera by a quarter of (0.3, 0.1, 0).
  int moved = 0;
  for (const PathSpaceState& s : f.samplePaths(200, 4)) {
    const WindowInstant here = *f.time.instant(s.tau);
    if (here.frame == 3) continue;
    for (const PathVertex& v : s.path.vertices) {
      const PathVertex w = placedAt(f.window, v, here, {here.frame + 1, here.shutterFraction});
      if (!movesWithTime(f.window, v)) {
        EXPECT_EQ(w.position(), v.position());
        EXPECT_EQ(areaScale(f.window, v, here), 1);
        continue;
      }
      const bool camera = v.type == VertexType::Camera;
      const Vec3f step = camera ? Vec3f{0.3f, 0.1f, 0} / 4 : Vec3f{0.4f, 0.2f, 0.3f} / 4;
      test_support::expectNear(w.position() - v.position(), step, 1e-4f);
      test_support::expectNear(w.hit.geometricNormal, v.hit.geometricNormal, 1e-5f);  // translations only
      // The quad is scaled by 2 along its width: twice the world area per shape area.
      EXPECT_NEAR(areaScale(f.window, v, here), camera || v.delta ? 1 : 2, 1e-5);
      ++moved;
    }
  }
  EXPECT_GT(moved, 20);
}

}  // namespace
}  // namespace pathfarm
