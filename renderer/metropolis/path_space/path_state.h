#pragma once
// The state of a path-space Metropolis chain over a window of frames (Veach and Guibas
// 1997; Van de Woestijne et al. 2017): a complete path x0 (on the lens) ... xk (on an
// emitter, or an environment direction) and the window time tau it lives at. The path's
// vertex list is the bidirectional one (renderer/bidirectional/complete_path.h): every
// surface vertex knows its object and its point in the object's shape space
// (SurfaceHit::object, shapePosition), so a vertex on an animated object can be moved to
// another time (vertex_motion.h), and whether it scattered by a Dirac lobe (`delta`).
#include "renderer/bidirectional/complete_path.h"
#include "renderer/metropolis/chain_target.h"
#include "renderer/metropolis/window_scene.h"

namespace pathfarm {

struct PathSpaceState {
  CompletePath path;  // path.time: the shutter fraction of tau in its frame
  double tau = 0;     // window time, in frames (window_time.h)
  // f(X) (complete_path.h, with the film's importance) where the path lands. A seed
  // regenerated from the bootstrap carries its bootstrap weight here instead
  // (path_space_target.h); `density` is always f*(X).
  Contribution contribution;
  double density = 0;  // the chain's density f*(X): the luminance of f(X)
};

// The state of `path` at window time `tau`, with f(X) evaluated in tau's frame; black
// (density 0) when the shutter is closed at tau or the path carries nothing.
PathSpaceState stateAt(const WindowScene& scene, CompletePath path, double tau);

}  // namespace pathfarm
