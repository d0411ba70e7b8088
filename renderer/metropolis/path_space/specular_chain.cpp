#include "renderer/metropolis/path_space/specular_chain.h"

#include <optional>

#include "renderer/bidirectional/connection.h"
#include "renderer/bidirectional/vertex_scattering.h"
#include "renderer/integrators/path_vertex.h"

namespace pathfarm {
namespace {

bool isReflection(const PathVertex& previous, const PathVertex& x, const PathVertex& next) {
  const Vec3f n = x.hit.geometricNormal;
  return dot(n, directionBetween(x, previous)) * dot(n, directionBetween(x, next)) > 0;
}

// The direction in which a ray travelling along `travel` leaves the delta vertex x by its
// Dirac reflection (or refraction). Every material puts its Dirac lobes at one end of
// uLobe's range (vertex_scattering.cpp), so both ends are tried.
std::optional<Vec3f> deltaDirection(const Scene& scene, const PathVertex& x, Vec3f travel, bool reflection) {
  const ShadedVertex shaded(scene, x.hit, travel);
  for (const float uLobe : {0.0f, 0x1.fffffep-1f}) {
    const auto s = shaded.bsdf.sample(shaded.wo, uLobe, {0.5f, 0.5f});
    if (s && s->delta && (s->wi.z * shaded.wo.z > 0) == reflection) return normalize(shaded.frame.toWorld(s->wi));
  }
  return std::nullopt;
}

// Where the ray from exactly `origin` along `direction` meets the tangent plane of `hit`,
// which a ray from an offset origin found: without the offset, re-tracing a chain the
// other way comes back to the same points (to rounding), which makes moves reversible.
void onExactRay(const BdptScene& bdpt, float time, Vec3f origin, Vec3f direction, SurfaceHit& hit) {
  const float along = dot(direction, hit.geometricNormal);
  if (along == 0) return;
  hit.position = origin + direction * (dot(hit.position - origin, hit.geometricNormal) / along);
  hit.shapePosition = bdpt.geometry.shapeToWorld(hit.object, time).inversePoint(hit.position);
}

bool animated(const BdptScene& bdpt, const SurfaceHit& hit) {
  const PreparedShape& shape = bdpt.geometry.shot().shape(hit.object);
  return shape.animated || shape.deforming;
}

// The symmetric geometry term |cos at p| |cos at q| / |p - q|^2 (a solid angle at p for
// an environment q).
double symmetricGeometry(const PathVertex& p, const PathVertex& q) {
  return std::abs(dot(p.hit.geometricNormal, directionBetween(p, q))) * toAreaDensity(p, q, 1.0f);
}

}  // namespace

std::vector<SpecularChain> specularChainsOf(const std::vector<PathVertex>& x) {
  std::vector<SpecularChain> chains;
  const int k = static_cast<int>(x.size()) - 1;
  for (int i = 1; i < k; ++i) {
    if (!x[vertexIndex(i)].delta) continue;
    const int a = i - 1;
    while (i < k && x[vertexIndex(i)].delta) ++i;
    chains.push_back({a, i});
  }
  return chains;
}

std::optional<PathVertex> regenerate(const BdptScene& bdpt, float time, const PathVertex& from, Vec3f direction,
                                     const PathVertex& wanted) {
  SurfaceHit hit;
  const bool hitSomething = bdpt.geometry.intersect({offsetRayOrigin(from.hit, direction), direction}, time, hit);
  if (hitSomething) onExactRay(bdpt, time, from.position(), direction, hit);
  PathVertex v;
  v.type = wanted.type;
  v.delta = wanted.delta;
  if (wanted.type == VertexType::Environment) {
    if (hitSomething) return std::nullopt;
    v.direction = direction;
    return v;
  }
  if (!hitSomething || wanted.type == VertexType::Camera) return std::nullopt;
  if (animated(bdpt, hit) != animated(bdpt, wanted.hit)) return std::nullopt;
  v.hit = hit;
  if (wanted.type == VertexType::Surface && !wanted.delta && !isConnectible(bdpt.scene(), v)) return std::nullopt;
  return v;
}

bool edgeVisible(const BdptScene& bdpt, float time, const PathVertex& cameraSide, const PathVertex& lightSide) {
  if (lightSide.type == VertexType::Environment) return bdpt.geometry.escapes(cameraSide.hit, lightSide.direction, time);
  if (cameraSide.type == VertexType::Camera) return bdpt.geometry.connects(lightSide.hit, cameraSide.position(), time);
  return bdpt.geometry.connects(cameraSide.hit, lightSide.position(), time);
}

bool retraceChain(const BdptScene& bdpt, float time, const std::vector<PathVertex>& original, SpecularChain chain,
                  ChainDirection direction, std::vector<PathVertex>& vertices) {
  const bool fromCamera = direction == ChainDirection::FromCamera;
  const int step = fromCamera ? 1 : -1;
  const int anchor = fromCamera ? chain.a : chain.b, far = fromCamera ? chain.b : chain.a;
  const PathVertex& start = vertices[vertexIndex(anchor)];
  const PathVertex& first = vertices[vertexIndex(anchor + step)];
  if (!(fromCamera ? edgeVisible(bdpt, time, start, first) : edgeVisible(bdpt, time, first, start))) return false;
  Vec3f travel = directionBetween(start, first);
  for (int i = anchor + step; i != far; i += step) {
    const bool reflection = isReflection(original[vertexIndex(i - 1)], original[vertexIndex(i)], original[vertexIndex(i + 1)]);
    const auto out = deltaDirection(bdpt.scene(), vertices[vertexIndex(i)], travel, reflection);
    if (!out) return false;
    const auto next = regenerate(bdpt, time, vertices[vertexIndex(i)], *out, original[vertexIndex(i + step)]);
    if (!next) return false;
    vertices[vertexIndex(i + step)] = *next;
    travel = *out;
  }
  return true;
}

bool straightenChains(const BdptScene& bdpt, float time, std::vector<PathVertex>& x) {
  const std::vector<PathVertex> original = x;
  for (const SpecularChain& c : specularChainsOf(original))
    if (!retraceChain(bdpt, time, original, c, ChainDirection::FromCamera, x)) return false;
  return true;
}

double regenerationDensity(const Scene& scene, const std::vector<PathVertex>& x, SpecularChain chain,
                           ChainDirection direction) {
  double fromCamera = 1;
  for (int j = chain.a + 2; j <= chain.b; ++j) fromCamera *= toAreaDensity(x[vertexIndex(j - 1)], x[vertexIndex(j)], 1.0f);
  if (direction == ChainDirection::FromCamera) return fromCamera;
  // n_b / n_a: each refraction multiplies the index by the material's ior entering it.
  double indexRatio = 1;
  for (int i = chain.a + 1; i < chain.b; ++i) {
    const PathVertex& v = x[vertexIndex(i)];
    if (isReflection(x[vertexIndex(i - 1)], v, x[vertexIndex(i + 1)])) continue;
    const double ior = ShadedVertex::materialOf(scene, v.hit).ior;
    const bool cameraSideOutside = dot(v.hit.geometricNormal, directionBetween(v, x[vertexIndex(i - 1)])) > 0;
    indexRatio *= cameraSideOutside ? ior : 1 / ior;
  }
  return fromCamera * symmetricGeometry(x[vertexIndex(chain.a)], x[vertexIndex(chain.a + 1)]) /
         (indexRatio * indexRatio * symmetricGeometry(x[vertexIndex(chain.b - 1)], x[vertexIndex(chain.b)]));
}

}  // namespace pathfarm
