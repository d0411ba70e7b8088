#pragma once
// Detailed balance of a path-space mutation, checked with the move X -> Y and the move
// Y -> X that must undo it, each computed on its own: the second lands on X again, the
// transition densities each claims agree with the other's, and
//   f(X) T(X -> Y) a(X -> Y) = f(Y) T(Y -> X) a(Y -> X)
// holds with T(Y -> X) from the move back. The two moves see the vertex positions
// rounded differently (to about 1e-6, more after long specular chains), hence 1e-3; with
// T(Y -> X) from the forward move alone the identity holds to 1e-6.
#include <gtest/gtest.h>

#include <algorithm>

#include "renderer/metropolis/path_space/path_mutation.h"
#include "test_support.h"

namespace pathfarm::test_support {

inline double acceptance(double fFrom, double forward, double fTo, double reverse) {
  return std::min(1.0, fTo * reverse / (fFrom * forward));
}

// Whether a path has an edge shorter than `length` (between surface points in a corner,
// whose g = cos / d^2 float positions leave imprecise to a few 1e-3).
inline bool hasShortEdge(const PathSpaceState& x, float length) {
  const auto& v = x.path.vertices;
  for (size_t i = 1; i < v.size(); ++i)
    if (v[i].isSurfaceLike() && v[i - 1].type != VertexType::Environment &&
        pathfarm::length(v[i].position() - v[i - 1].position()) < length)
      return true;
  return false;
}

// Whether the pair was checked (the move there proposed a path carrying light, without
// corner edges shorter than 0.05 in either path).
inline bool expectDetailedBalance(const PathSpaceState& x, const PathMutation& there, const PathMutation& back) {
  if (!(there.proposed.density > 0) || !(there.forward > 0)) return false;
  if (hasShortEdge(x, 0.05f) || hasShortEdge(there.proposed, 0.05f)) return false;
  EXPECT_GT(back.proposed.density, 0);
  const auto& a = x.path.vertices;
  const auto& b = back.proposed.path.vertices;
  if (!(back.proposed.density > 0) || a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) expectNear(a[i].position(), b[i].position(), 2e-4f);
  EXPECT_NEAR(back.proposed.tau, x.tau, 1e-9);
  EXPECT_NEAR(there.reverse / back.forward, 1, 1e-3);
  EXPECT_NEAR(back.reverse / there.forward, 1, 1e-3);
  const double fx = x.density, fy = there.proposed.density;
  const double lhs = fx * there.forward * acceptance(fx, there.forward, fy, there.reverse);
  // f(X) from X itself: at grazing angles f is too sensitive to rounding to re-evaluate.
  const double rhs = fy * back.forward * acceptance(fy, back.forward, fx, back.reverse);
  EXPECT_NEAR(lhs / rhs, 1, 1e-3);
  const double rhsExact = fy * there.reverse * acceptance(fy, there.reverse, fx, there.forward);
  EXPECT_NEAR(lhs / rhsExact, 1, 1e-6);
  return true;
}

}  // namespace pathfarm::test_support
