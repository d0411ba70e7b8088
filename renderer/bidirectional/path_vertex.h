#pragma once
// A vertex of a bidirectional light path (Veach 1997, chapter 10). A complete path is
// x0 (on the camera's lens) ... xk (on an emitter, or a direction to the environment);
// a camera subpath holds x0, x1, ... and a light subpath xk, xk-1, ..., each in the order
// it was sampled.
//
// Densities are in area measure at the vertex they belong to, except for environment
// vertices (directions), whose densities are solid-angle densities at their neighbour.
// A density "from a delta vertex" (a vertex scattered by a Dirac lobe) is stored as 0:
// it cannot be evaluated, and in multiple importance sampling it is the same on both
// sides and cancels (mis_weight.h).
#include <vector>

#include "renderer/accel/surface_hit.h"

namespace pathfarm {

// Vertex i of a path's std::vector: the path algorithms count vertices in int.
inline size_t vertexIndex(int i) { return static_cast<size_t>(i); }

enum class VertexType : uint8_t {
  Camera,       // x0: hit.position is the lens point, hit.geometricNormal the viewing axis
  Surface,      // a scattering point (it may also emit, when a camera subpath ends on an emitter)
  Light,        // a point on a surface emitter, or a point or spot light, that a light subpath starts from
  Environment,  // the environment or a directional light, in `direction` from the previous vertex
};

struct PathVertex {
  VertexType type = VertexType::Surface;
  SurfaceHit hit;
  Vec3f direction;     // Environment: the unit direction towards it
  bool delta = false;  // Surface: scattered by a Dirac lobe; such a vertex cannot be connected
  // Light and Environment ends: the punctual light (index into Scene::punctualLights) the
  // vertex is on, or -1. A point or spot light's vertex keeps the light's position in
  // hit.position and the direction it points along in hit.geometricNormal, with
  // hit.object -1. No walk can hit a punctual light: densities of sampling one from a
  // neighbour are 0, so only strategies that start light subpaths on it count.
  int punctual = -1;
  // Subpath throughput: the estimate f/p of the subpath up to this vertex, without the
  // scattering at this vertex. Camera subpaths: the product of BSDF sample weights, as
  // in the path tracer. Light subpaths: see subpath.h.
  Rgb beta;
  float pdfFwd = 0;  // density of this vertex sampled from the previous vertex of its subpath
  float pdfRev = 0;  // density of this vertex sampled from the next one, walking the other way

  Vec3f position() const { return hit.position; }
  bool isSurfaceLike() const { return type == VertexType::Surface || type == VertexType::Light; }
  bool isPunctual() const { return punctual >= 0; }
};

using Subpath = std::vector<PathVertex>;

}  // namespace pathfarm
