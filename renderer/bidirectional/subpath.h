#pragma once
// Camera and light subpaths by random walks (Veach 1997, section 10.2), without Russian
// roulette, so that a subpath's length depends only on where it goes and on maxDepth.
//
// Uniform numbers, in order (a fixed number per vertex, so that primary-sample-space
// mutations keep their meaning):
//   camera subpath: per scattering vertex 1 (lobe) + 2 (direction); the film position,
//     shutter time and lens are the caller's (the frame renderer reads them from the
//     pixel's stream in the path tracer's order).
//   light subpath: 1 (emitter choice) + 2 (point) + 2 (emission direction), then per
//     scattering vertex 1 + 2.
//
// Light subpath throughput: beta at y0 (the emitter point) is 1 / p(y0), as Le is applied
// by the connections that use y0 (it depends on the side they leave it by); at a later
// vertex y_m it is the estimate of Le * prod g * prod fs over the subpath, divided by its
// density, and so carries 1 / |cos at y_m| of the edge it arrived on: the measurement
// contribution holds that cosine in fs(y_m) (vertex_scattering.h), which connections apply.
// A light subpath that starts on the environment is that single vertex: the environment
// is reached by the camera strategies only (s = 0, and s = 1 as next-event estimation),
// see mis_weight.h.
#include "renderer/bidirectional/bdpt_scene.h"
#include "renderer/bidirectional/path_vertex.h"
#include "renderer/bidirectional/uniform_source.h"

namespace pathfarm {

// The camera subpath of the ray through continuous pixel position `film` with lens
// sample `lens`: x0 on the lens, then at most `maxVertices` - 1 more vertices. Replaces
// `path`'s contents; returns its size.
int generateCameraSubpath(const BdptScene& bdpt, float time, Vec2f film, Vec2f lens, UniformSource& u,
                          int maxVertices, Subpath& path);
// A light subpath of at most `maxVertices` vertices; empty when the scene has no emitter.
int generateLightSubpath(const BdptScene& bdpt, float time, UniformSource& u, int maxVertices, Subpath& path);

// The longest subpaths a scene's maxDepth allows: a camera subpath holds the camera, up
// to maxDepth scattering vertices and the emitter it may hit; a light subpath one fewer.
inline int maxCameraVertices(const BdptScene& bdpt) { return bdpt.maxDepth + 2; }
inline int maxLightVertices(const BdptScene& bdpt) { return bdpt.maxDepth + 1; }

}  // namespace pathfarm
