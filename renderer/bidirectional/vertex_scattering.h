#pragma once
// Local quantities of path vertices, shared by subpath sampling, connections and the
// evaluation of complete paths, so that all of them agree.
//
// The measurement contribution (radiance form, as the path tracer estimates it):
//   f(X) = We(x0 -> x1) cos0 * prod_{i<k} g(x_i, x_i+1) * prod_{0<i<k} fs(x_i) * Le(xk -> xk-1)
// with g(a, b) = |cos at b| / |a - b|^2 (geometric normal of b, the vertex on the light
// side of the edge; no cosine at a point or spot light; 1 for an environment direction), fs(x_i) = Bsdf::eval(to x_i-1,
// to x_i+1), which holds the shading cosine at x_i towards the light side, and We the
// film's importance (camera_importance.h): a pixel's value is W H times the integral of
// f over the paths that land in it. With shading normals equal to geometric ones
// this is Veach's f(X).
#include "renderer/bidirectional/bdpt_scene.h"
#include "renderer/bidirectional/path_vertex.h"

namespace pathfarm {

// Unit direction from `from` to `to` (either may be an environment direction).
Vec3f directionBetween(const PathVertex& from, const PathVertex& to);
// Converts a solid-angle density at `from` into the area density at `to`.
float toAreaDensity(const PathVertex& from, const PathVertex& to, float solidAnglePdf);
// g(cameraSide, lightSide) of the measurement contribution above.
float edgeFactor(const PathVertex& cameraSide, const PathVertex& lightSide);

// fs at a surface vertex for light arriving from `towardLight` and leaving towards
// `towardCamera` (unit world directions). At a delta vertex, the coefficient of the
// Dirac lobe connecting the two directions (its sample weight times its selection
// probability), or black when none does.
Rgb scattering(const Scene& scene, const PathVertex& x, Vec3f towardCamera, Vec3f towardLight);
// Radiance an emitter vertex (surface or environment) sends towards `toward`; intensity
// for a point or spot light, irradiance for a directional one.
Rgb emitted(const Scene& scene, const PathVertex& x, Vec3f toward);

// Area density (solid angle for an environment `to`) of sampling `to` from `from`, where
// `from` was reached from `before` (null when `from` starts its subpath: the camera, or an
// emitter point emitting cosine-weighted). 0 from a delta vertex and from the environment.
float vertexDensity(const BdptScene& bdpt, float time, const PathVertex* before, const PathVertex& from,
                    const PathVertex& to);
// Density of choosing the light end `x` of a path as light subpaths do: area density on
// a surface emitter, solid-angle density for the environment, the probability of the
// choice for a punctual light.
float lightStartDensity(const BdptScene& bdpt, float time, const PathVertex& x);
// The light end on punctual light `light` at `time` (see PathVertex::punctual).
PathVertex punctualLightEnd(const BdptScene& bdpt, float time, int light);

}  // namespace pathfarm
