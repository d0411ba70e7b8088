#include "renderer/metropolis/path_space/path_walk.h"

#include "renderer/bidirectional/vertex_scattering.h"
#include "renderer/integrators/path_vertex.h"
#include "renderer/math/frame.h"
#include "renderer/math/sampling.h"

namespace pathfarm {
namespace {

// The probability that the BSDF at delta vertex x, seen from `before`, chooses the Dirac
// lobe that sends light towards `to`: BsdfSample::pdf of a delta sample. Dirac lobes sit
// at the ends of uLobe's range (vertex_scattering.cpp).
double lobeSelection(const Scene& scene, const PathVertex& before, const PathVertex& x, const PathVertex& to) {
  const ShadedVertex shaded(scene, x.hit, directionBetween(before, x));
  const Vec3f wi = shaded.frame.toLocal(directionBetween(x, to));
  for (const float uLobe : {0.0f, 0x1.fffffep-1f}) {
    const auto s = shaded.bsdf.sample(shaded.wo, uLobe, {0.5f, 0.5f});
    if (s && s->delta && dot(s->wi, wi) > 1 - 1e-4f) return s->pdf;
  }
  return 0;
}

}  // namespace

std::optional<PathVertex> walkFrom(const BdptScene& bdpt, float time, const PathVertex* before, PathVertex& from,
                                   SampleStream& random) {
  Ray ray;
  if (from.type == VertexType::Camera) {
    const Vec2f film{random.next1D() * static_cast<float>(bdpt.camera.width()),
                     random.next1D() * static_cast<float>(bdpt.camera.height())};
    ray = bdpt.camera.camera().generateRay(film, {0.5f, 0.5f}, bdpt.seconds(time));
    ray.origin = from.position();
  } else if (from.type == VertexType::Environment) {
    return std::nullopt;  // light subpaths do not leave the environment (subpath.h)
  } else if (!before && from.isPunctual()) {
    const PunctualLight& light = bdpt.scene().punctualLights[static_cast<size_t>(from.punctual)];
    const auto emission = light.sampleEmission(random.next2D(), from.hit.geometricNormal);
    if (!emission) return std::nullopt;
    ray = {offsetRayOrigin(from.hit, emission->direction), emission->direction};
  } else if (!before) {
    const Vec3f local = sampleCosineHemisphere(random.next2D());
    if (!(local.z > 0)) return std::nullopt;
    const Vec3f direction = normalize(Frame::fromNormal(from.hit.geometricNormal).toWorld(local));
    ray = {offsetRayOrigin(from.hit, direction), direction};
  } else {
    const float uLobe = random.next1D();
    const Vec2f uDirection = random.next2D();
    const ShadedVertex shaded(bdpt.scene(), from.hit, directionBetween(*before, from));
    const auto s = shaded.bsdf.sample(shaded.wo, uLobe, uDirection);
    if (!s) return std::nullopt;
    from.delta = s->delta;
    const Vec3f direction = normalize(shaded.frame.toWorld(s->wi));
    ray = {offsetRayOrigin(from.hit, direction), direction};
  }
  PathVertex next;
  if (!bdpt.geometry.intersect(ray, time, next.hit)) {
    next.type = VertexType::Environment;
    next.direction = ray.direction;
  }
  return next;
}

std::optional<PathVertex> sampleLightEnd(const BdptScene& bdpt, float time, SampleStream& random) {
  const float uLight = random.next1D();
  const Vec2f uPoint = random.next2D();
  if (bdpt.lights.empty()) return std::nullopt;
  const LightChoice choice = bdpt.lights.choose(uLight);
  if (choice.kind == LightChoice::Kind::Punctual) return punctualLightEnd(bdpt, time, choice.index);
  PathVertex end;
  if (choice.kind == LightChoice::Kind::Environment) {
    const auto sky = bdpt.lights.sampleEnvironment(uPoint);
    if (!sky) return std::nullopt;
    end.type = VertexType::Environment;
    end.direction = sky->direction;
    return end;
  }
  const auto point = bdpt.lights.sampleEmitterPoint(bdpt.geometry, time, uLight, uPoint);
  if (!point) return std::nullopt;
  end.type = VertexType::Light;
  end.hit = point->hit;
  return end;
}

double walkDensity(const BdptScene& bdpt, float time, const PathVertex* before, const PathVertex& from,
                   const PathVertex& to) {
  if (!from.delta) return vertexDensity(bdpt, time, before, from, to);
  if (!before) return 0;
  return lobeSelection(bdpt.scene(), *before, from, to) * toAreaDensity(from, to, 1.0f);
}

}  // namespace pathfarm
