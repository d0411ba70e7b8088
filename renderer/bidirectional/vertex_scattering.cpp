#include "renderer/bidirectional/vertex_scattering.h"

#include "renderer/integrators/path_vertex.h"

namespace pathfarm {
namespace {

// Bsdf::eval is zero on Dirac lobes; their coefficient comes from sampling them. Every
// material's lobe choice puts its Dirac lobes at one end of uLobe's range (reflection
// below F, transmission above, the plastic's coating first), so trying both ends finds
// the lobe that maps wo onto wi, if there is one.
Rgb deltaCoefficient(const Bsdf& bsdf, Vec3f wo, Vec3f wi) {
  for (const float uLobe : {0.0f, 0x1.fffffep-1f}) {
    const auto s = bsdf.sample(wo, uLobe, {0.5f, 0.5f});
    if (s && s->delta && dot(s->wi, wi) > 1 - 1e-4f) return s->weight * s->pdf;
  }
  return {};
}

float cosineAt(const PathVertex& x, Vec3f direction) {
  return x.isPunctual() ? 1.0f : std::abs(dot(x.hit.geometricNormal, direction));
}

const PunctualLight& punctualLightOf(const Scene& scene, const PathVertex& x) {
  return scene.punctualLights[static_cast<size_t>(x.punctual)];
}

}  // namespace

Vec3f directionBetween(const PathVertex& from, const PathVertex& to) {
  if (to.type == VertexType::Environment) return to.direction;
  if (from.type == VertexType::Environment) return -from.direction;
  return normalize(to.position() - from.position());
}

float toAreaDensity(const PathVertex& from, const PathVertex& to, float solidAnglePdf) {
  if (to.type == VertexType::Environment) return solidAnglePdf;
  const Vec3f d = to.position() - from.position();
  const float distanceSquared = dot(d, d);
  if (!(distanceSquared > 0)) return 0;
  return solidAnglePdf * cosineAt(to, d / std::sqrt(distanceSquared)) / distanceSquared;
}

float edgeFactor(const PathVertex& cameraSide, const PathVertex& lightSide) {
  return toAreaDensity(cameraSide, lightSide, 1.0f);
}

Rgb scattering(const Scene& scene, const PathVertex& x, Vec3f towardCamera, Vec3f towardLight) {
  const ShadedVertex shaded(scene, x.hit, -towardCamera);
  const Vec3f wi = shaded.frame.toLocal(towardLight);
  if (x.delta) return deltaCoefficient(shaded.bsdf, shaded.wo, wi);
  return shaded.bsdf.eval(shaded.wo, wi);
}

Rgb emitted(const Scene& scene, const PathVertex& x, Vec3f toward) {
  if (x.isPunctual()) {
    const PunctualLight& light = punctualLightOf(scene, x);
    return x.type == VertexType::Environment ? light.intensity : light.intensityToward(toward, x.hit.geometricNormal);
  }
  if (x.type == VertexType::Environment) return scene.environment.radiance(x.direction);
  if (x.type == VertexType::Camera || dot(x.hit.geometricNormal, toward) <= 0) return {};
  return emissionAt(scene, scene.objects[static_cast<size_t>(x.hit.object)], x.hit.uv);
}

float vertexDensity(const BdptScene& bdpt, float time, const PathVertex* before, const PathVertex& from,
                    const PathVertex& to) {
  if (from.type == VertexType::Environment || from.delta || to.isPunctual()) return 0;
  const Vec3f direction = directionBetween(from, to);
  float pdf = 0;
  if (from.isPunctual()) {
    pdf = punctualLightOf(bdpt.scene(), from).emissionPdf(direction, from.hit.geometricNormal);
  } else if (from.type == VertexType::Camera) {
    pdf = bdpt.camera.directionPdf(from.position(), direction, bdpt.seconds(time));
  } else if (!before) {
    // An emitter point emits cosine-weighted into its front hemisphere.
    pdf = std::max(0.0f, dot(from.hit.geometricNormal, direction)) * kInvPi;
  } else {
    const ShadedVertex shaded(bdpt.scene(), from.hit, -directionBetween(from, *before));
    pdf = shaded.bsdf.pdf(shaded.wo, shaded.frame.toLocal(direction));
  }
  return toAreaDensity(from, to, pdf);
}

float lightStartDensity(const BdptScene& bdpt, float time, const PathVertex& x) {
  if (x.isPunctual()) return bdpt.lights.punctualProbability(x.punctual);
  if (x.type == VertexType::Environment) return bdpt.lights.environmentPdf(x.direction);
  return bdpt.lights.emitterPointPdf(bdpt.geometry, x.hit, time);
}

PathVertex punctualLightEnd(const BdptScene& bdpt, float time, int light) {
  const PunctualLight& source = bdpt.scene().punctualLights[static_cast<size_t>(light)];
  const double seconds = bdpt.seconds(time);
  PathVertex end;
  end.punctual = light;
  if (source.type == PunctualType::Directional) {
    end.type = VertexType::Environment;
    end.direction = -source.forward(seconds);
    return end;
  }
  end.type = VertexType::Light;
  end.hit.object = -1;
  end.hit.position = source.position(seconds);
  end.hit.geometricNormal = source.forward(seconds);
  end.hit.shadingNormal = end.hit.geometricNormal;
  return end;
}

}  // namespace pathfarm
