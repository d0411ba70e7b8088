#pragma once
// Connects a camera subpath's first t vertices with a light subpath's first s vertices:
// one strategy (s, t) of bidirectional path tracing (Veach 1997, section 10.2), weighted
// by multiple importance sampling (mis_weight.h).
//
// Contributions are estimates of f(X) / p(X) with the film's importance We
// (camera_importance.h), so every strategy has the same scale: a pixel's value is W H
// times the expectation of the contributions that land in it, for camera ray positions
// uniform over the film. In a per-pixel estimator with spp camera samples and as many
// light subpaths, a pixel's camera strategies (t >= 2) average to its value and each
// light-tracing contribution (t = 1) is splatted at its raster position divided by spp.
#include <optional>

#include "renderer/bidirectional/bdpt_scene.h"
#include "renderer/bidirectional/mis_weight.h"
#include "renderer/bidirectional/path_vertex.h"
#include "renderer/bidirectional/uniform_source.h"

namespace pathfarm {

struct StrategySample {
  Rgb contribution;       // misWeight * unweighted
  Rgb unweighted;         // f / p of the strategy alone
  float misWeight = 0;
  // t = 1 (light tracing): the raster position it lands on, elsewhere than the camera
  // subpath's pixel; other strategies land where the camera subpath started.
  bool lightTracing = false;
  Vec2f raster;
};

// Strategy (s, t), s + t >= 2, t >= 1, s <= light.size(), t <= camera.size(). Nothing
// when it contributes nothing (impossible, occluded, black). Light tracing draws its lens
// point from `connection` (2 numbers; the other strategies draw none). With `path`, also
// returns the complete path x0 ... xk (vertex_scattering.h) and, with `densities`, its
// strategy densities, for Metropolis seeds.
std::optional<StrategySample> connectStrategy(const BdptScene& bdpt, float time, const Subpath& camera,
                                              const Subpath& light, int s, int t, UniformSource& connection,
                                              Subpath* path = nullptr, PathDensities* densities = nullptr);

// Calls f(s, t) for every strategy of two subpaths within maxDepth, in the fixed order
// (t ascending, then s ascending) in which every user draws connection numbers.
template <class F>
void forEachStrategy(const BdptScene& bdpt, const Subpath& camera, const Subpath& light, F&& f) {
  for (int t = 1; t <= static_cast<int>(camera.size()); ++t)
    for (int s = 0; s <= static_cast<int>(light.size()); ++s)
      if (s + t >= 2 && s + t - 2 <= bdpt.maxDepth) f(s, t);
}

// Whether a connection may end at `x`: cameras, emitters and surfaces with a non-delta lobe.
bool isConnectible(const Scene& scene, const PathVertex& x);

}  // namespace pathfarm
