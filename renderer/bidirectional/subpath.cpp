#include "renderer/bidirectional/subpath.h"

#include "renderer/bidirectional/vertex_scattering.h"
#include "renderer/integrators/path_vertex.h"
#include "renderer/math/frame.h"
#include "renderer/math/sampling.h"

namespace pathfarm {
namespace {

enum class Direction { FromCamera, FromLight };

// Light subpaths sample the adjoint: directions towards the camera given the one towards
// the light. For a non-delta lobe, fs / pdf comes from Bsdf::eval in radiance form. A
// Dirac lobe's weight is for radiance; the adjoint drops the 1 / eta^2 of refraction and
// swaps the cosines (Veach 1997, section 5.2): weight * eta^2 * |cos light| / |cos camera|.
Rgb adjointWeight(const ShadedVertex& shaded, const Material& material, const BsdfSample& s) {
  if (!s.delta) return shaded.bsdf.eval(s.wi, shaded.wo) / s.pdf;
  const Vec3f wo = shaded.wo;
  float scale = std::abs(wo.z) / std::abs(s.wi.z);
  if (wo.z * s.wi.z < 0) {
    const float eta = wo.z > 0 ? material.ior : 1 / material.ior;
    scale *= eta * eta;
  }
  return s.weight * scale;
}

// The densities that the newest vertex of `path` settles: its own from its predecessor,
// and its predecessor's predecessor's sampled the other way. They are evaluated from the
// vertices' positions, exactly as for complete paths (vertex_scattering.h), so that MIS
// weights agree bit for bit however a path was sampled.
void recordDensities(const BdptScene& bdpt, float time, Subpath& path) {
  const size_t n = path.size() - 1;
  path[n].pdfFwd = vertexDensity(bdpt, time, n >= 2 ? &path[n - 2] : nullptr, path[n - 1], path[n]);
  if (n >= 2) path[n - 2].pdfRev = vertexDensity(bdpt, time, &path[n], path[n - 1], path[n - 2]);
}

// Extends `path` (holding at least its first vertex) along `ray`, carrying `carry` (the
// next vertex's beta before the arrival cosine of light subpaths).
void randomWalk(const BdptScene& bdpt, float time, Ray ray, Rgb carry, UniformSource& u, int maxVertices,
                Direction direction, Subpath& path) {
  const Scene& scene = bdpt.scene();
  while (static_cast<int>(path.size()) < maxVertices) {
    PathVertex v;
    SurfaceHit hit;
    if (!bdpt.geometry.intersect(ray, time, hit)) {
      if (direction == Direction::FromCamera && !scene.environment.isBlack()) {
        v.type = VertexType::Environment;
        v.direction = ray.direction;
        v.beta = carry;
        path.push_back(v);
        recordDensities(bdpt, time, path);
      }
      return;
    }
    v.hit = hit;
    v.beta = carry;
    if (direction == Direction::FromLight) {
      const float cosArrival = std::abs(dot(hit.geometricNormal, ray.direction));
      if (!(cosArrival > 0)) return;
      v.beta = carry / cosArrival;
    }
    path.push_back(v);
    recordDensities(bdpt, time, path);
    if (static_cast<int>(path.size()) >= maxVertices) return;

    const float uLobe = u.next1D();
    const Vec2f uDirection = u.next2D();
    const ShadedVertex shaded(scene, hit, ray.direction);
    const auto s = shaded.bsdf.sample(shaded.wo, uLobe, uDirection);
    if (!s) return;
    PathVertex& here = path.back();
    const Vec3f next = normalize(shaded.frame.toWorld(s->wi));
    here.delta = s->delta;
    if (direction == Direction::FromCamera) {
      carry = here.beta * s->weight;
    } else {
      carry = here.beta * adjointWeight(shaded, ShadedVertex::materialOf(scene, hit), *s) *
              std::abs(dot(hit.geometricNormal, next));
    }
    if (carry.isBlack() || !carry.isFinite()) return;
    ray = {offsetRayOrigin(shaded.hit, next), next};
  }
}

}  // namespace

int generateCameraSubpath(const BdptScene& bdpt, float time, Vec2f film, Vec2f lens, UniformSource& u,
                          int maxVertices, Subpath& path) {
  path.clear();
  if (maxVertices < 1) return 0;
  const double seconds = bdpt.seconds(time);
  const Ray ray = bdpt.camera.camera().generateRay(film, lens, seconds);
  PathVertex x0;
  x0.type = VertexType::Camera;
  x0.hit.position = ray.origin;
  x0.hit.geometricNormal = bdpt.camera.viewDirection(seconds);
  x0.beta = Rgb(1);
  x0.pdfFwd = bdpt.camera.lensDensity();
  path.push_back(x0);
  // We cos / (the density of the ray) = 1, as in the path tracer (camera_importance.h).
  randomWalk(bdpt, time, ray, Rgb(1), u, maxVertices, Direction::FromCamera, path);
  return static_cast<int>(path.size());
}

int generateLightSubpath(const BdptScene& bdpt, float time, UniformSource& u, int maxVertices, Subpath& path) {
  path.clear();
  const float uLight = u.next1D();
  const Vec2f uPoint = u.next2D(), uDirection = u.next2D();
  if (maxVertices < 1 || bdpt.lights.empty()) return 0;
  const LightChoice choice = bdpt.lights.choose(uLight);
  PathVertex y0;
  if (choice.kind != LightChoice::Kind::Emitter) {
    if (choice.kind == LightChoice::Kind::Punctual) {
      y0 = punctualLightEnd(bdpt, time, choice.index);
    } else {
      const auto sky = bdpt.lights.sampleEnvironment(uPoint);
      if (!sky) return 0;
      y0.type = VertexType::Environment;
      y0.direction = sky->direction;
    }
    // From the vertex, as complete paths evaluate it, so that MIS weights agree bit for bit.
    y0.pdfFwd = lightStartDensity(bdpt, time, y0);
    if (!(y0.pdfFwd > 0)) return 0;
    y0.beta = Rgb(1 / y0.pdfFwd);
    path.push_back(y0);
    if (y0.type == VertexType::Environment) return 1;
    const PunctualLight& light = bdpt.scene().punctualLights[static_cast<size_t>(y0.punctual)];
    const auto emission = light.sampleEmission(uDirection, y0.hit.geometricNormal);
    if (!emission) return 1;
    // I beta / pdf: a point light has no emission cosine.
    randomWalk(bdpt, time, {offsetRayOrigin(y0.hit, emission->direction), emission->direction},
               emission->intensity * y0.beta / emission->pdf, u, maxVertices, Direction::FromLight, path);
    return static_cast<int>(path.size());
  }
  const auto point = bdpt.lights.sampleEmitterPoint(bdpt.geometry, time, uLight, uPoint);
  if (!point) return 0;
  y0.type = VertexType::Light;
  y0.hit = point->hit;
  y0.pdfFwd = point->pdfArea;
  y0.beta = Rgb(1 / point->pdfArea);
  path.push_back(y0);
  const Vec3f local = sampleCosineHemisphere(uDirection);
  const float pdf = cosineHemispherePdf(local.z);
  if (!(pdf > 0)) return 1;
  const Vec3f direction = normalize(Frame::fromNormal(y0.hit.geometricNormal).toWorld(local));
  // Le beta |cos| / (cos / pi): the emission cosine cancels.
  randomWalk(bdpt, time, {offsetRayOrigin(y0.hit, direction), direction}, point->radiance * y0.beta * kPi, u,
             maxVertices, Direction::FromLight, path);
  return static_cast<int>(path.size());
}

}  // namespace pathfarm
