#pragma once
// The path sampler of primary-sample-space Metropolis light transport (Kelemen et al.
// 2002) built on bidirectional path tracing, as in pbrt-v3's MLT integrator: a primary
// sample chooses one path depth and ONE strategy (s, t) of it, samples exactly the
// subpaths that strategy needs, and returns its MIS-weighted contribution times the
// number of strategies of that depth, so that the strategies of a depth together are an
// unbiased estimate of that depth's light.
//
// Streams (each a UniformSource over its own part of the primary sample vector):
//   camera:     2 (film position, uniform over the film) + 2 (lens), then the walk (subpath.h)
//   light:      the light subpath (subpath.h)
//   connection: 1 (the strategy), then the connection's numbers (connection.h)
// The shutter time is the caller's: one more primary coordinate, across a window of
// frames if it likes, that selects the BdptScene (frame) and `time`.
#include "renderer/bidirectional/bdpt_scene.h"
#include "renderer/bidirectional/path_vertex.h"
#include "renderer/bidirectional/uniform_source.h"

namespace pathfarm {

struct PrimarySampleStreams {
  UniformSource& camera;
  UniformSource& light;
  UniformSource& connection;
};

struct StrategyEvaluation {
  // MIS weight * f / p * (depth + 2), scaled as connection.h describes: the pixel
  // containing `raster` has W H times the expectation of the contributions landing in it.
  Rgb contribution;
  Vec2f raster;  // continuous pixel position
  int s = 0, t = 0;
};

// `depth` is the number of scattering events (0 ... maxDepth); the path has depth + 2
// vertices. The subpaths are scratch space (kept to avoid allocations).
StrategyEvaluation evaluateStrategy(const BdptScene& bdpt, float time, int depth, PrimarySampleStreams streams,
                                    Subpath& cameraScratch, Subpath& lightScratch);

}  // namespace pathfarm
