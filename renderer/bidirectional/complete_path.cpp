#include "renderer/bidirectional/complete_path.h"

#include "renderer/bidirectional/vertex_scattering.h"

namespace pathfarm {

PathMeasurement measure(const BdptScene& bdpt, const CompletePath& path) {
  PathMeasurement m;
  const std::vector<PathVertex>& x = path.vertices;
  const int k = path.length();
  // A punctual light has no area for the camera to see (connection.cpp).
  if (k < 1 || x[0].type != VertexType::Camera || (k == 1 && x[1].isPunctual())) return m;
  const Scene& scene = bdpt.scene();
  const double seconds = bdpt.seconds(path.time);
  const Vec3f first = directionBetween(x[0], x[1]);
  m.raster = bdpt.camera.raster(x[0].position(), first, seconds);
  Rgb f(bdpt.camera.importance(x[0].position(), first, seconds) * dot(first, x[0].hit.geometricNormal));
  for (int i = 0; i < k; ++i) f *= edgeFactor(x[static_cast<size_t>(i)], x[static_cast<size_t>(i + 1)]);
  // A zero-length edge (two vertices at one point, as a Metropolis mutation can propose)
  // has no direction: stop before a BSDF sees its NaN.
  if (f.isBlack()) return m;
  for (int i = 1; i < k; ++i) {
    const PathVertex& v = x[static_cast<size_t>(i)];
    f *= scattering(scene, v, directionBetween(v, x[static_cast<size_t>(i - 1)]),
                    directionBetween(v, x[static_cast<size_t>(i + 1)]));
  }
  f *= emitted(scene, x[static_cast<size_t>(k)], directionBetween(x[static_cast<size_t>(k)], x[static_cast<size_t>(k - 1)]));
  if (f.isBlack()) return m;
  for (int i = 0; i < k; ++i) {
    const PathVertex& a = x[static_cast<size_t>(i)];
    const PathVertex& b = x[static_cast<size_t>(i + 1)];
    const bool visible = b.type == VertexType::Environment ? bdpt.geometry.escapes(a.hit, b.direction, path.time)
                         : a.type == VertexType::Camera   ? bdpt.geometry.connects(b.hit, a.position(), path.time)
                                                          : bdpt.geometry.connects(a.hit, b.position(), path.time);
    if (!visible) return m;
  }
  m.f = f;
  return m;
}

PathDensities densitiesOf(const BdptScene& bdpt, const CompletePath& path) {
  const std::vector<PathVertex>& x = path.vertices;
  const int k = path.length();
  PathDensities d;
  d.resize(k + 1);
  d.environmentEnd = x.back().type == VertexType::Environment;
  for (int i = 0; i <= k; ++i) {
    const auto at = static_cast<size_t>(i);
    d.delta[at] = x[at].delta;
    if (i >= 1) d.fromCamera[at] = vertexDensity(bdpt, path.time, i >= 2 ? &x[at - 2] : nullptr, x[at - 1], x[at]);
    d.fromLight[at] = i == k ? lightStartDensity(bdpt, path.time, x[at])
                             : vertexDensity(bdpt, path.time, i + 2 <= k ? &x[at + 2] : nullptr, x[at + 1], x[at]);
  }
  d.fromCamera[0] = bdpt.camera.lensDensity();
  return d;
}

void completePathsOf(const BdptScene& bdpt, float time, const Subpath& camera, const Subpath& light,
                     Vec2f cameraRaster, UniformSource& connection, std::vector<WeightedPath>& out) {
  forEachStrategy(bdpt, camera, light, [&](int s, int t) {
    WeightedPath w;
    const auto sample = connectStrategy(bdpt, time, camera, light, s, t, connection, &w.path.vertices);
    if (!sample || sample->contribution.isBlack()) return;
    w.path.time = time;
    w.contribution = sample->contribution;
    w.raster = sample->lightTracing ? sample->raster : cameraRaster;
    w.s = s;
    w.t = t;
    out.push_back(std::move(w));
  });
}

}  // namespace pathfarm
