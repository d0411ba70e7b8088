#pragma once
// Complete light paths x0 (on the lens) ... xk (on an emitter, or an environment
// direction) for path-space Metropolis light transport (Veach and Guibas 1997): a path
// is a vertex list that can be re-evaluated after its vertices moved.
//
// A vertex list is valid when x0 is a Camera vertex, x1 ... xk-1 are Surface vertices
// with their hits (position, normals, uv, object, primitive as FrameGeometry::intersect
// gives them; `delta` set where the path scatters by a Dirac lobe), and xk is a Light
// vertex (a surface emitter hit) or an Environment vertex (`direction` set). beta and the
// stored densities are not read.
//
// Delta vertices: f(X) uses the coefficient of the Dirac lobe (vertex_scattering.h) in
// place of the distribution, and densities sampled from a delta vertex count as 1
// (mis_weight.h); both are exact for ratios between paths with the same delta vertices,
// which is all the Metropolis acceptance ratio and the MIS weights need.
#include <optional>
#include <vector>

#include "renderer/bidirectional/bdpt_scene.h"
#include "renderer/bidirectional/connection.h"
#include "renderer/bidirectional/mis_weight.h"
#include "renderer/bidirectional/path_vertex.h"

namespace pathfarm {

struct CompletePath {
  std::vector<PathVertex> vertices;
  float time = 0;  // shutter fraction of the frame the BdptScene places

  int length() const { return static_cast<int>(vertices.size()) - 1; }  // k, the number of edges
};

struct PathMeasurement {
  Rgb f;                 // the measurement contribution (vertex_scattering.h), visibility included
  std::optional<Vec2f> raster;  // where x0 -> x1 lands on the film
};

PathMeasurement measure(const BdptScene& bdpt, const CompletePath& path);
// The densities of every strategy for `path`, evaluated from its vertices alone; the
// density of strategy (s, t) is strategyDensity(densities, t) * lens density.
PathDensities densitiesOf(const BdptScene& bdpt, const CompletePath& path);

// One strategy of a bidirectional sample as a complete path: the seed pool of path-space
// Metropolis. contribution = misWeight * f / p, scaled as connection.h describes.
struct WeightedPath {
  CompletePath path;
  Rgb contribution;
  Vec2f raster;
  int s = 0, t = 0;
};

// Every strategy of a camera and a light subpath (sampled at `time`) that contributes,
// appended to `out`; `cameraRaster` is where the camera subpath started. Draws the same
// numbers from `connection` as the frame renderer does for the same subpaths.
void completePathsOf(const BdptScene& bdpt, float time, const Subpath& camera, const Subpath& light,
                     Vec2f cameraRaster, UniformSource& connection, std::vector<WeightedPath>& out);

}  // namespace pathfarm
