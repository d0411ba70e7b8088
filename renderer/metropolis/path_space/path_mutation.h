#pragma once
// What a path-space mutation proposes: the new state and the transition densities both
// ways, T(X -> Y) and T(Y -> X), in the path measure of the states (area measure with the
// formal Dirac convention of path_walk.h); the acceptance ratio is
// f(Y) T(Y -> X) / (f(X) T(X -> Y)).
#include "renderer/metropolis/path_space/path_state.h"

namespace pathfarm {

struct PathMutation {
  PathSpaceState proposed;  // density 0 when the mutation failed or carries nothing
  double forward = 0;       // T(X -> Y)
  double reverse = 0;       // T(Y -> X)
};

}  // namespace pathfarm
