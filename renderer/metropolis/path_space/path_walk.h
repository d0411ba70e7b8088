#pragma once
// Random walks that extend a path from one of its vertices, and the densities with which
// they sample a vertex, for the path-space mutations (Veach and Guibas 1997). A walk
// samples what bidirectional subpaths sample (subpath.h): from the camera a direction
// uniform over the film, from an emitter point a cosine-weighted direction, from a point
// or spot light a direction uniform over its sphere or cone, from a surface a BSDF
// sample; a new light end is an emitter point, a punctual light or an environment
// direction, chosen by the light sampler.
//
// Densities are area densities (solid angle for environment directions), as
// vertexDensity() gives them, except from a delta vertex: there the Dirac density is
// written formally as the lobe's selection probability times g(from, to) = |cos at to| /
// |to - from|^2 (Veach 1997, section 11.4), the convention under which f(X) is written
// (complete_path.h), so that f / T is the path's throughput.
#include <optional>

#include "renderer/bidirectional/bdpt_scene.h"
#include "renderer/bidirectional/path_vertex.h"
#include "renderer/sampling/sample_stream.h"

namespace pathfarm {

// The vertex a walk reaches from `from`, which was reached from `before` (null when
// `from` is the camera or a light end, which emits cosine-weighted); sets from.delta to
// whether a Dirac lobe was chosen there. An environment vertex when the ray escapes;
// nothing when no direction could be sampled.
std::optional<PathVertex> walkFrom(const BdptScene& bdpt, float time, const PathVertex* before, PathVertex& from,
                                   SampleStream& random);
// A new light end: an emitter point, a punctual light or an environment direction.
std::optional<PathVertex> sampleLightEnd(const BdptScene& bdpt, float time, SampleStream& random);

// The density with which walkFrom(before, from) yields `to`, as above.
double walkDensity(const BdptScene& bdpt, float time, const PathVertex* before, const PathVertex& from,
                   const PathVertex& to);

}  // namespace pathfarm
