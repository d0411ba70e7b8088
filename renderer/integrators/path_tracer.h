#pragma once
// Unidirectional path tracing with next-event estimation, combined with BSDF sampling by
// multiple importance sampling (Veach 1997, power heuristic), and Russian roulette.
#include <cstdint>

#include "renderer/accel/frame_geometry.h"
#include "renderer/decomposition/path_decomposer.h"
#include "renderer/integrators/light_sampler.h"
#include "renderer/sampling/sample_stream.h"

namespace pathfarm {

// Rays traced, for throughput figures.
struct RayCounts {
  uint64_t closestHit = 0;
  uint64_t shadow = 0;
};

// What a decomposing render learns about a sample's path besides its radiance.
struct PathRecord {
  PathDecomposer* decomposer = nullptr;  // splits the radiance into components
  bool hit = false;                      // whether the camera ray hit anything, and where
  SurfaceHit primary;
};

struct PathTracerSettings {
  int maxDepth = 8;        // scattering events; 1 is direct lighting only
  int rouletteDepth = 3;   // Russian roulette from this many scattering events on
};

class PathTracer {
 public:
  PathTracer(const FrameGeometry& geometry, const LightSampler& lights, PathTracerSettings settings)
      : geometry_(geometry), lights_(lights), settings_(settings) {}

  // The radiance arriving along `ray` at shutter time `time` (in [0,1]). Draws a fixed
  // number of uniform numbers per bounce from `stream`, so that dimensions line up
  // between correlated samples.
  // With a record, also splits the path into components and reports the first hit; the
  // radiance returned is the same bits either way.
  Rgb radiance(Ray ray, float time, SampleStream& stream, RayCounts& counts, PathRecord* record = nullptr) const;
  // Follows `ray` only until the decomposer has each component's features: through specular
  // vertices to the first vertex whose sampled lobe is non-specular (no later vertex is a
  // component's first D vertex then, path_decomposer.h). No light is gathered.
  void traceFeatures(Ray ray, float time, SampleStream& stream, RayCounts& counts, PathDecomposer& decomposer) const;

 private:
  const FrameGeometry& geometry_;
  const LightSampler& lights_;
  PathTracerSettings settings_;
};

}  // namespace pathfarm
