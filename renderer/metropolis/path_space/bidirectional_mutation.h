#pragma once
// The bidirectional mutation of Veach and Guibas 1997 (Veach 1997, section 11.4.2): delete
// the vertices strictly between x_l and x_m of X (0 <= l < m <= k + 1; m = k + 1 deletes
// the light end too), then add n new vertices, t of them by a walk from x_l and n - t by
// a walk from x_m (or from a new light end), and connect the two walks.
//
//   P(l, m):  the number of deleted edges m - l = d in [1, k + 1] with probability
//             proportional to 2^-(d - 1), then l uniform among the k + 2 - d places
//             (l = k, m = k + 1 keeps the light end x_k as x_l, to scatter there: for an
//             environment direction, which cannot, the proposal fails);
//   P(n):     n in {nd - 1, nd, nd + 1} (nd = m - l - 1 deleted vertices) with weights
//             1/4, 1/2, 1/4 among the lengths allowed (at most maxDepth scattering
//             vertices, a new light end when it was deleted, never n = nd = 0);
//   t:        uniform in [0, n].
//
// T(X -> Y) = P(l, m) P(n) sum_t' 1/(n + 1) p_t'(new vertices of Y), the sum over every
// split t' of the new vertices into camera and light walks that could have made them
// (its connection edge between two non-delta vertices), p_t' the product of their walk
// densities (path_walk.h). The reverse deletes the new vertices of Y and adds back X's.
// The time stays, except when the whole path after the camera vertex is deleted (l = 0,
// m = k + 1): then tau is drawn anew uniformly over the window's open time (density
// 1 / open length both ways) and the camera vertex placed there, so that chains reach
// every frame however short the temporal perturbation's reach D is (with D below the
// closed part of a frame, temporal moves alone never leave a frame). The camera must be
// a pinhole: its lens point is never resampled.
#include "renderer/metropolis/path_space/path_mutation.h"
#include "renderer/sampling/sample_stream.h"

namespace pathfarm {

PathMutation bidirectionalMutation(const WindowScene& scene, const PathSpaceState& current, SampleStream& random);

// The pieces of T, for tests: P(l, m) for a path of k edges, and T(X -> Y) for the
// mutation that kept X's vertices [0, l] and [m, k] (Y keeps them as [0, l] and
// [m', k'], m' = l + 1 + its number of new vertices).
double deletionProbability(int k, int l, int m);
bool renewsTime(int k, int l, int m);
double bidirectionalDensity(const WindowScene& scene, const PathSpaceState& x, const PathSpaceState& y, int l, int m);

}  // namespace pathfarm
