#include "renderer/decomposition/specular_chain.h"

#include "renderer/materials/bsdf.h"

namespace pathfarm {
namespace {

bool isDielectric(MaterialType type) {
  return type == MaterialType::Dielectric || type == MaterialType::RoughDielectric;
}

// Snell's law for a unit direction arriving at a surface with unit normal n (outward)
// and interior index `ior`; nothing under total internal reflection.
template <class V>
std::optional<V> refractThrough(V d, V n, double ior) {
  double cosIn = -dot(d, n);
  double eta = 1 / ior;  // n(incident side) / n(transmitted side)
  if (cosIn < 0) {
    n = -n;
    cosIn = -cosIn;
    eta = ior;
  }
  const double sin2Out = eta * eta * (1 - cosIn * cosIn);
  if (sin2Out >= 1) return std::nullopt;
  const double cosOut = std::sqrt(1 - sin2Out);
  return d * eta + n * (eta * cosIn - cosOut);
}

template <class V>
V reflectOff(V d, V n) {
  return d - n * (2 * dot(d, n));
}

struct ChainSearch {
  const FrameGeometry& geometry;
  const LpeAutomaton& automaton;
  int component;
  float time;
  SpecularChain chain;

  // Depth-first over the specular lobes that keep the component alive; the first chain
  // found in lobe order wins, so the result is deterministic.
  bool search(const Ray& ray, int state, int depth) {
    SurfaceHit hit;
    if (!geometry.intersect(ray, time, hit)) return false;
    const Scene& scene = geometry.shot().scene();
    const Material& material =
        scene.materials[static_cast<size_t>(scene.objects[static_cast<size_t>(hit.object)].material)];
    const LobeList lobes = Bsdf(material, Rgb(), scene.roughnessThreshold).lobes();
    bool diffuse = false;
    for (int l = 0; l < lobes.count; ++l) diffuse |= lobes.lobes[l].symbol == LobeSymbol::D;
    if (diffuse && automaton.alive(automaton.next(state, PathSymbol::D), component)) {
      chain.endpoint = hit.object;
      return depth > 0;  // at depth 0 the component's vertex is what the camera sees
    }
    if (depth + 1 >= kMaxChainVertices) return false;
    for (int l = 0; l < lobes.count; ++l) {
      const LobeSymbol symbol = lobes.lobes[l].symbol;
      if (symbol == LobeSymbol::D) continue;
      const int next = automaton.next(state, symbol == LobeSymbol::R ? PathSymbol::R : PathSymbol::T);
      if (!automaton.alive(next, component)) continue;
      const bool refracts = symbol == LobeSymbol::T;
      // Thin-walled transmission (metallic-roughness) passes straight through: index 1.
      const double ior = isDielectric(material.type) ? material.ior : 1.0;
      const Vec3f n = hit.shadingNormal;
      Vec3f direction = reflectOff(ray.direction, n);
      if (refracts) {
        const auto refracted = refractThrough(ray.direction, n, ior);
        if (!refracted) continue;
        direction = normalize(*refracted);
      }
      chain.links.push_back({hit.object, refracts, ior});
      if (search({offsetRayOrigin(hit, direction), direction}, next, depth + 1)) return true;
      chain.links.pop_back();
    }
    return false;
  }
};

}  // namespace

std::optional<SpecularChain> findSpecularChain(const FrameGeometry& geometry, const LpeAutomaton& automaton,
                                               int component, Ray ray, float time) {
  ChainSearch search{geometry, automaton, component, time, {}};
  if (!search.search(ray, automaton.next(automaton.initial(), PathSymbol::E), 0)) return std::nullopt;
  return search.chain;
}

std::optional<ChainPath> ChainTracer::trace(Vec2d film, double seconds) const {
  ChainPath path;
  path.seconds = seconds;
  path.film = film;
  const PinholeCamera::Placed camera = camera_.at(seconds);
  path.eye = camera.position();
  path.eyeVelocity = camera.velocity();
  Vec3d origin = path.eye, direction = camera.direction(film);
  double minDistance = 0;
  const auto visit = [&](int object) {
    const auto hit = shapes_[static_cast<size_t>(object)].intersect(origin, direction, minDistance, seconds);
    if (!hit || !isFinite(hit->position) || !isFinite(hit->normal)) return false;
    path.vertices.push_back({*hit, dot(direction, hit->normal) < 0});
    origin = hit->position;
    // Leaving a surface: skip the surface itself, whatever rounding put the point on.
    minDistance = 1e-7 * (1 + maxAbs(origin));
    return true;
  };
  for (const ChainLink& link : chain_.links) {
    if (!visit(link.object)) return std::nullopt;
    const Vec3d n = path.vertices.back().surface.normal;
    if (link.refracts) {
      const auto refracted = refractThrough(direction, n, link.ior);
      if (!refracted) return std::nullopt;
      direction = normalize(*refracted);
    } else {
      direction = reflectOff(direction, n);
    }
  }
  if (!visit(chain_.endpoint)) return std::nullopt;
  return path;
}

Vec3d ChainTracer::endpointTarget(Vec3d shapePosition, double seconds) const {
  return shapes_[static_cast<size_t>(chain_.endpoint)].placementAt(seconds).point(shapePosition);
}

bool isUnoccluded(const ChainPath& path, const FrameGeometry& geometry, float time) {
  Vec3f from = path.eye.toFloat();
  for (const ChainVertex& vertex : path.vertices) {
    const Vec3f to = vertex.surface.position.toFloat();
    const Vec3f along = to - from;
    const float distance = length(along);
    // Start and stop a little off the surfaces at both ends, which the segment touches.
    const float startGap = surfaceEpsilon(from), endGap = surfaceEpsilon(to);
    if (distance > startGap + endGap) {
      const Vec3f direction = along / distance;
      if (geometry.occluded(from + direction * startGap, direction, distance - startGap - endGap, time)) return false;
    }
    from = to;
  }
  return true;
}

bool sameSides(const ChainPath& a, const ChainPath& b) {
  if (a.vertices.size() != b.vertices.size()) return false;
  for (size_t i = 0; i < a.vertices.size(); ++i)
    if (a.vertices[i].front != b.vertices[i].front) return false;
  return true;
}

}  // namespace pathfarm
