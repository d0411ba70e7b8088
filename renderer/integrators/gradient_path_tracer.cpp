#include "renderer/integrators/gradient_path_tracer.h"

#include <cmath>

#include "renderer/integrators/path_vertex.h"
#include "renderer/integrators/shift_mapping.h"
#include "renderer/math/sampling.h"

namespace pathfarm {
namespace {

// What every vertex of one sample's paths is traced and shaded against: the frame at the
// sample's time, and the ray counts it adds to.
struct SampleContext {
  const Scene& scene;
  const FrameGeometry& geometry;
  const LightSampler& lights;
  float time;
  RayCounts& counts;

  bool intersect(const Ray& ray, SurfaceHit& hit) const {
    ++counts.closestHit;
    return geometry.intersect(ray, time, hit);
  }
  // The shadow ray of a next-event estimate from `from`.
  bool unoccluded(const SurfaceHit& from, const LightSample& light) const {
    ++counts.shadow;
    return std::isinf(light.distance) ? geometry.escapes(from, light.direction, time)
                                      : geometry.connects(from, from.position + light.direction * light.distance, time);
  }
  Rgb arrivingEmission(bool found, const SurfaceHit& hit, Vec3f incoming) const {
    if (!found) return scene.environment.radiance(incoming);
    const SceneObject& object = scene.objects[static_cast<size_t>(hit.object)];
    return object.isEmitter() && dot(incoming, hit.geometricNormal) < 0 ? emissionAt(scene, object, hit.uv) : Rgb();
  }
  // Density with which next-event estimation from `from` yields what a ray along
  // `incoming` found.
  float lightPdfOf(bool found, const SurfaceHit& hit, Vec3f from, Vec3f incoming) const {
    if (!found) return scene.environment.isBlack() ? 0.0f : lights.environmentPdf(incoming);
    return lights.pdf(geometry, from, hit, time);
  }
};

// The base path at its current vertex, and the step that reached it, for weighting the
// emission found there.
struct BasePath {
  Ray ray;         // the ray that reached the current vertex
  SurfaceHit hit;  // the current vertex
  bool found = false;
  Rgb throughput{1.0f};
  float previousPdf = 0;
  bool previousDelta = true;
  Vec3f previousPosition;
};

// An offset path while it follows its base path. Densities are kept relative to the
// base path's: `throughput` is f(y) J / p(x) and `ratio` is p(y) J / p(x) of the prefix,
// so the MIS weight compares p(x) with p(y) J in the base path's measure.
struct OffsetPath {
  enum class Mode { Replay, Reconnected, Dead } mode = Mode::Dead;
  Ray ray;                   // replay: the ray that reached the current vertex
  SurfaceHit hit;            // replay: the current vertex
  bool found = false;        // replay: whether the ray hit anything
  Vec3f incoming;            // direction the current vertex was reached along
  bool firstShared = false;  // reconnected, and the current vertex is the first shared one
  Rgb throughput{1.0f};
  float ratio = 1;
  // The last step, for weighting the emission it finds: the offset's density of its
  // direction (selection probability for a delta lobe), its Jacobian, the ratio before it.
  float stepPdf = 0, stepJacobian = 1, ratioBefore = 1;
  bool stepDelta = true;
  Vec3f previousPosition;
};

using OffsetPaths = std::array<OffsetPath, 4>;

// The offsets' own vertices: replayed ones at their own hit, reconnected ones at the
// base's vertex, reached from their own direction at the first shared vertex and from
// the base's after it, where they are the base's vertex itself.
struct OffsetVertices {
  std::array<std::optional<ShadedVertex>, 4> own;
  std::array<const ShadedVertex*, 4> at{};
};

// The base's next-event estimate at its vertex; the offsets aim at the same light point.
struct BaseNextEvent {
  LightSample light;
  Vec3f wi;        // local at the base's vertex
  Rgb f;
  float bsdfPdf;   // of BSDF sampling reaching the light point
  bool visible;
  Rgb contribution;
};

// The base path's scattering from its current vertex to the next, which the offsets shift.
struct BaseStep {
  BsdfSample scattered;
  Vec3f direction;   // world
  bool connectable;  // the current vertex
  float survive;     // the Russian roulette's survival probability, 1 before it starts
  Ray next;
  SurfaceHit nextHit;
  bool nextFound;
  bool nextConnectable;  // the next vertex, or the environment
};

// The power-heuristic weight of the strategy with density `chosen` among the base's
// densities {light, bsdf} and the offset's {light, bsdf}, the latter already times J and
// the prefix ratio.
float misWeight(float chosen, float baseLight, float baseBsdf, float offsetLight, float offsetBsdf) {
  const float denominator =
      baseLight * baseLight + baseBsdf * baseBsdf + offsetLight * offsetLight + offsetBsdf * offsetBsdf;
  return denominator > 0 && std::isfinite(denominator) ? chosen * chosen / denominator : 0;
}

void addWeighted(GradientSample& out, size_t k, float weight, const Rgb& base, const Rgb& offset) {
  out.base[k] += base * weight;
  out.offset[k] += offset * weight;
  out.difference[k] += (offset - base) * weight;
}

// The offset paths start along the camera rays through the neighbouring pixels.
OffsetPaths startOffsetPaths(const SampleContext& context, const std::array<std::optional<Ray>, 4>& offsetRays) {
  OffsetPaths offsets;
  for (size_t k = 0; k < 4; ++k) {
    if (!offsetRays[k]) continue;
    OffsetPath& o = offsets[k];
    o.mode = OffsetPath::Mode::Replay;
    o.ray = *offsetRays[k];
    o.incoming = o.ray.direction;
    o.found = context.intersect(o.ray, o.hit);
  }
  return offsets;
}

// The emission the base's BSDF sampling found, and each offset's emission at its own
// vertex, under the MIS weight of the BSDF strategy.
void addBsdfSampledEmission(const SampleContext& context, const BasePath& base, const OffsetPaths& offsets,
                            GradientSample& out) {
  const Rgb emitted = context.arrivingEmission(base.found, base.hit, base.ray.direction);
  const float lightPdf =
      base.previousDelta ? 0 : context.lightPdfOf(base.found, base.hit, base.previousPosition, base.ray.direction);
  const Rgb contribution = base.throughput * emitted;
  out.radiance += contribution * (base.previousDelta ? 1 : powerHeuristic(base.previousPdf, lightPdf));
  for (size_t k = 0; k < 4; ++k) {
    const OffsetPath& o = offsets[k];
    if (o.mode == OffsetPath::Mode::Dead) {
      addWeighted(out, k, misWeight(base.previousPdf, lightPdf, base.previousPdf, 0, 0), contribution, Rgb());
      continue;
    }
    const bool replay = o.mode == OffsetPath::Mode::Replay;
    const bool offsetFound = replay ? o.found : base.found;
    const SurfaceHit& offsetHit = replay ? o.hit : base.hit;
    const float offsetLightPdf =
        o.stepDelta ? 0 : context.lightPdfOf(offsetFound, offsetHit, o.previousPosition, o.incoming);
    const float scale = o.ratioBefore * o.stepJacobian;
    addWeighted(out, k,
                misWeight(base.previousPdf, lightPdf, base.previousPdf, scale * offsetLightPdf, scale * o.stepPdf),
                contribution, o.throughput * context.arrivingEmission(offsetFound, offsetHit, o.incoming));
  }
}

// Retires the replayed offsets that escaped at the last step and shades the others'
// vertices. `baseHit` is the base's vertex as found, before shading flipped its normal.
void shadeOffsetVertices(const Scene& scene, const ShadedVertex& vertex, const SurfaceHit& baseHit,
                         OffsetPaths& offsets, OffsetVertices& vertices) {
  for (size_t k = 0; k < 4; ++k) {
    OffsetPath& o = offsets[k];
    if (o.mode == OffsetPath::Mode::Replay && !o.found) o.mode = OffsetPath::Mode::Dead;  // escaped earlier
    if (o.mode == OffsetPath::Mode::Replay) vertices.at[k] = &vertices.own[k].emplace(scene, o.hit, o.incoming);
    if (o.mode == OffsetPath::Mode::Reconnected)
      vertices.at[k] = o.firstShared ? &vertices.own[k].emplace(scene, baseHit, o.incoming) : &vertex;
  }
}

// Offset k's next-event estimate towards the base's light point, weighted together with
// the base's.
void addOffsetNextEvent(const SampleContext& context, const BaseNextEvent& base, const ShadedVertex& vertex,
                        const OffsetPath& o, const ShadedVertex* offsetVertex, const BounceSamples& u, size_t k,
                        GradientSample& out) {
  const LightSample& light = base.light;
  if (o.mode == OffsetPath::Mode::Dead) {
    addWeighted(out, k, misWeight(light.pdf, light.pdf, base.bsdfPdf, 0, 0), base.contribution, Rgb());
    return;
  }
  const ShadedVertex& y = *offsetVertex;
  const bool sharesVertex = &y == &vertex;  // then its light sample, f and pdf are the base's
  // Light points depend on the random numbers alone: the offset aims at the same
  // point, so the step's Jacobian is the ratio of the solid-angle densities.
  const auto offsetLight =
      o.mode == OffsetPath::Mode::Replay
          ? context.lights.sample(context.geometry, y.hit.position, context.time, u.light, u.lightPoint)
          : std::optional<LightSample>(light);
  if (!offsetLight || !y.bsdf.hasNonDeltaLobe()) {
    addWeighted(out, k, misWeight(light.pdf, light.pdf, base.bsdfPdf, 0, 0), base.contribution, Rgb());
    return;
  }
  const Vec3f offsetWi = sharesVertex ? base.wi : y.frame.toLocal(offsetLight->direction);
  const Rgb offsetF = sharesVertex ? base.f : y.bsdf.eval(y.wo, offsetWi);
  const float jacobian = light.pdf / offsetLight->pdf;
  bool offsetVisible = base.visible;
  if (o.mode == OffsetPath::Mode::Replay && !offsetF.isBlack())
    offsetVisible = context.unoccluded(y.hit, *offsetLight);
  const Rgb offset = offsetVisible ? o.throughput * offsetF * offsetLight->radiance / offsetLight->pdf : Rgb();
  const float scale = o.ratio * jacobian;
  addWeighted(out, k,
              misWeight(light.pdf, light.pdf, base.bsdfPdf, scale * offsetLight->pdf,
                        light.delta ? 0 : scale * (sharesVertex ? base.bsdfPdf : y.bsdf.pdf(y.wo, offsetWi))),
              base.contribution, offset);
}

// Next-event estimation towards the light point the base's random numbers choose, from
// the base's vertex and from each offset's.
void addNextEventEstimation(const SampleContext& context, const ShadedVertex& vertex, const Rgb& throughput,
                            const BounceSamples& u, const OffsetPaths& offsets, const OffsetVertices& offsetVertices,
                            GradientSample& out) {
  if (!vertex.bsdf.hasNonDeltaLobe() || context.lights.empty()) return;
  const auto light = context.lights.sample(context.geometry, vertex.hit.position, context.time, u.light, u.lightPoint);
  if (!light) return;
  const Vec3f wi = vertex.frame.toLocal(light->direction);
  const Rgb f = vertex.bsdf.eval(vertex.wo, wi);
  // BSDF sampling never reaches a punctual light: its technique's density is 0.
  const float bsdfPdf = light->delta ? 0 : vertex.bsdf.pdf(vertex.wo, wi);
  const bool visible = !f.isBlack() && context.unoccluded(vertex.hit, *light);
  const BaseNextEvent base{*light, wi, f, bsdfPdf, visible,
                           visible ? throughput * f * light->radiance / light->pdf : Rgb()};
  out.radiance += base.contribution * powerHeuristic(light->pdf, base.bsdfPdf);
  for (size_t k = 0; k < 4; ++k)
    addOffsetNextEvent(context, base, vertex, offsets[k], offsetVertices.at[k], u, k, out);
}

// Samples the base's BSDF at `vertex`, plays Russian roulette and traces the ray to the
// base's next vertex, shading it ahead into `vertexAhead` to see whether it is
// connectable. Nothing when the base path ends here.
std::optional<BaseStep> scatterBasePath(const SampleContext& context, const ShadedVertex& vertex,
                                        const BounceSamples& u, bool roulette, Rgb& throughput,
                                        std::optional<ShadedVertex>& vertexAhead) {
  const auto scattered = vertex.bsdf.sample(vertex.wo, u.lobe, u.direction);
  if (!scattered || scattered->weight.isBlack()) return std::nullopt;
  throughput *= scattered->weight;
  const Vec3f direction = normalize(vertex.frame.toWorld(scattered->wi));
  float survive = 1;
  if (roulette) {
    survive = std::min(1.0f, throughput.maxComponent());
    if (u.roulette >= survive) return std::nullopt;
    throughput *= 1.0f / survive;
  }
  const Ray next{offsetRayOrigin(vertex.hit, direction), direction};
  SurfaceHit nextHit;
  const bool nextFound = context.intersect(next, nextHit);
  if (nextFound) vertexAhead.emplace(context.scene, nextHit, direction);
  const bool nextConnectable = !nextFound || isConnectable(vertexAhead->bsdf);
  return BaseStep{*scattered, direction, isConnectable(vertex.bsdf), survive, next, nextHit, nextFound,
                  nextConnectable};
}

// A reconnected offset shares the base's vertex: it takes the base's direction. Only the
// first shared vertex sees a different incoming direction; from the next one on the
// factors are the base's.
void followBasePath(OffsetPath& o, const ShadedVertex& y, const BaseStep& step) {
  const BsdfSample& scattered = step.scattered;
  if (o.firstShared) {
    const Rgb f = y.bsdf.eval(y.wo, scattered.wi);
    const float pdf = y.bsdf.pdf(y.wo, scattered.wi);
    o.throughput *= f / scattered.pdf;
    o.ratio *= pdf / scattered.pdf;
    o.stepPdf = pdf;
    o.firstShared = false;
  } else {
    o.throughput *= scattered.weight;
    o.stepPdf = scattered.pdf;
  }
  o.stepJacobian = 1;
  o.stepDelta = scattered.delta;
  o.incoming = step.direction;
}

// Reconnects the offset's vertex `y` to the base's next vertex (or follows the base out
// into the environment). False when the connection is blocked or carries nothing.
bool reconnectOffsetPath(const SampleContext& context, OffsetPath& o, const ShadedVertex& y,
                         const ShadedVertex& vertex, const BaseStep& step) {
  std::optional<Reconnection> link = step.nextFound
                                         ? reconnect(y.hit.position, vertex.hit.position, step.nextHit)
                                         : std::optional<Reconnection>(Reconnection{step.direction, 0, 1});
  ++context.counts.shadow;
  const bool open = link && (step.nextFound ? context.geometry.connects(y.hit, step.nextHit.position, context.time)
                                            : context.geometry.escapes(y.hit, step.direction, context.time));
  if (!open) return false;
  const Vec3f wi = y.frame.toLocal(link->direction);
  const Rgb f = y.bsdf.eval(y.wo, wi);
  const float pdf = y.bsdf.pdf(y.wo, wi);
  if (f.isBlack()) return false;
  o.throughput *= f * (link->jacobian / step.scattered.pdf);
  o.ratio *= pdf * link->jacobian / step.scattered.pdf;
  o.stepPdf = pdf;
  o.stepJacobian = link->jacobian;
  o.stepDelta = false;
  o.incoming = link->direction;
  o.mode = OffsetPath::Mode::Reconnected;
  o.firstShared = true;
  return true;
}

// Replays the base's random numbers at the offset's own vertex `y` and traces the ray to
// its next vertex. False when the replay has no counterpart of the base's step, or when
// the shift would not be invertible.
bool replayOffsetPath(const SampleContext& context, OffsetPath& o, const ShadedVertex& y, const BaseStep& step,
                      const BounceSamples& u) {
  // A discrete choice must meet a discrete one: a delta lobe has no density to compare
  // with a glossy one.
  const auto own = y.bsdf.sample(y.wo, u.lobe, u.direction);
  if (!own || own->weight.isBlack() || own->delta != step.scattered.delta) return false;
  o.throughput *= own->weight;
  o.stepPdf = own->pdf;
  o.stepJacobian = step.scattered.pdf / own->pdf;
  o.stepDelta = own->delta;
  o.incoming = normalize(y.frame.toWorld(own->wi));
  o.ray = {offsetRayOrigin(y.hit, o.incoming), o.incoming};
  o.found = context.intersect(o.ray, o.hit);
  // Invertibility: from a connectable pair, the shift back would reconnect to a
  // connectable replayed vertex, and so reach another base path. No shift, then.
  return !(step.connectable && isConnectable(y.bsdf) &&
           (!o.found || isConnectable(ShadedVertex(context.scene, o.hit, o.incoming).bsdf)));
}

// The shift of one bounce (shift_mapping.h): the offset at vertex `y` follows the base's
// step from `vertex` by sharing, reconnection or replay, and dies where it cannot.
void shiftOffsetPath(const SampleContext& context, OffsetPath& o, const ShadedVertex& y, const ShadedVertex& vertex,
                     const BaseStep& step, const BounceSamples& u) {
  o.ratioBefore = o.ratio;
  o.previousPosition = y.hit.position;
  bool shifted = true;
  if (o.mode == OffsetPath::Mode::Reconnected)
    followBasePath(o, y, step);
  else if (step.connectable && isConnectable(y.bsdf) && step.nextConnectable)
    shifted = reconnectOffsetPath(context, o, y, vertex, step);
  else
    shifted = replayOffsetPath(context, o, y, step, u);
  if (!shifted) {
    o.mode = OffsetPath::Mode::Dead;
    return;
  }
  if (step.survive < 1) {
    // The base's roulette decides for both; the offset, sampled on its own, would have
    // survived with its own probability.
    o.throughput *= 1.0f / step.survive;
    const float own = o.ratio > 0 ? std::min(1.0f, o.throughput.maxComponent() * step.survive / o.ratio) : 0;
    o.ratio *= own / step.survive;
    o.ratioBefore *= own / step.survive;
  }
}

}  // namespace

GradientSample GradientPathTracer::trace(const Ray& cameraRay, const std::array<std::optional<Ray>, 4>& offsetRays,
                                         float time, SampleStream& stream, RayCounts& counts) const {
  const Scene& scene = geometry_.shot().scene();
  const SampleContext context{scene, geometry_, lights_, time, counts};

  GradientSample out;
  BasePath base;
  base.ray = cameraRay;
  base.found = context.intersect(base.ray, base.hit);
  // A camera ray that escapes sees the sky directly, which takes no part in the
  // differences: the offsets would add nothing, so their rays are not traced (4 of the 5
  // rays of such a sample).
  OffsetPaths offsets;
  if (base.found) offsets = startOffsetPaths(context, offsetRays);
  // The base's vertex, shaded once: the previous bounce shaded it to see whether it is
  // connectable.
  std::optional<ShadedVertex> vertexAhead;

  for (int depth = 0;; ++depth) {
    if (depth == 0)
      out.direct = context.arrivingEmission(base.found, base.hit, base.ray.direction);
    else
      addBsdfSampledEmission(context, base, offsets, out);
    if (!base.found || depth >= settings_.maxDepth) break;

    const BounceSamples u(stream);
    if (!vertexAhead) vertexAhead.emplace(scene, base.hit, base.ray.direction);
    const ShadedVertex vertex = *vertexAhead;
    vertexAhead.reset();
    OffsetVertices offsetVertices;
    shadeOffsetVertices(scene, vertex, base.hit, offsets, offsetVertices);
    addNextEventEstimation(context, vertex, base.throughput, u, offsets, offsetVertices, out);

    const std::optional<BaseStep> step =
        scatterBasePath(context, vertex, u, depth + 1 >= settings_.rouletteDepth, base.throughput, vertexAhead);
    if (!step) break;
    for (size_t k = 0; k < 4; ++k)
      if (offsets[k].mode != OffsetPath::Mode::Dead)
        shiftOffsetPath(context, offsets[k], *offsetVertices.at[k], vertex, *step, u);

    base.ray = step->next;
    base.hit = step->nextHit;
    base.found = step->nextFound;
    base.previousPdf = step->scattered.pdf;
    base.previousDelta = step->scattered.delta;
    base.previousPosition = vertex.hit.position;
  }
  return out;
}

}  // namespace pathfarm
