#include "renderer/integrators/gradient_path_tracer.h"

#include <cmath>

#include "renderer/integrators/path_vertex.h"
#include "renderer/integrators/shift_mapping.h"
#include "renderer/math/sampling.h"

namespace pathfarm {
namespace {

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

}  // namespace

GradientSample GradientPathTracer::trace(const Ray& cameraRay, const std::array<std::optional<Ray>, 4>& offsetRays,
                                         float time, SampleStream& stream, RayCounts& counts) const {
  const Scene& scene = geometry_.shot().scene();
  const auto arrivingEmission = [&](bool found, const SurfaceHit& hit, Vec3f incoming) {
    if (!found) return scene.environment.radiance(incoming);
    const SceneObject& object = scene.objects[static_cast<size_t>(hit.object)];
    return object.isEmitter() && dot(incoming, hit.geometricNormal) < 0 ? emissionAt(scene, object, hit.uv) : Rgb();
  };
  // Density with which next-event estimation from `from` yields what a ray along
  // `incoming` found.
  const auto lightPdfOf = [&](bool found, const SurfaceHit& hit, Vec3f from, Vec3f incoming) {
    if (!found) return scene.environment.isBlack() ? 0.0f : lights_.environmentPdf(incoming);
    return lights_.pdf(geometry_, from, hit, time);
  };
  const auto intersect = [&](const Ray& ray, SurfaceHit& hit) {
    ++counts.closestHit;
    return geometry_.intersect(ray, time, hit);
  };

  GradientSample out;
  Ray ray = cameraRay;
  SurfaceHit hit;
  bool found = intersect(ray, hit);
  // A camera ray that escapes sees the sky directly, which takes no part in the
  // differences: the offsets would add nothing, so their rays are not traced (4 of the 5
  // rays of such a sample).
  std::array<OffsetPath, 4> offsets;
  for (size_t k = 0; k < 4 && found; ++k) {
    if (!offsetRays[k]) continue;
    OffsetPath& o = offsets[k];
    o.mode = OffsetPath::Mode::Replay;
    o.ray = *offsetRays[k];
    o.incoming = o.ray.direction;
    o.found = intersect(o.ray, o.hit);
  }
  Rgb throughput(1.0f);
  float previousPdf = 0;
  bool previousDelta = true;
  Vec3f previousPosition;
  // The base's vertex, shaded once: the previous bounce shaded it to see whether it is
  // connectable.
  std::optional<ShadedVertex> vertexAhead;

  for (int depth = 0;; ++depth) {
    const Rgb emitted = arrivingEmission(found, hit, ray.direction);
    if (depth == 0) {
      out.direct = emitted;
    } else {
      const float lightPdf = previousDelta ? 0 : lightPdfOf(found, hit, previousPosition, ray.direction);
      const Rgb base = throughput * emitted;
      out.radiance += base * (previousDelta ? 1 : powerHeuristic(previousPdf, lightPdf));
      for (size_t k = 0; k < 4; ++k) {
        const OffsetPath& o = offsets[k];
        if (o.mode == OffsetPath::Mode::Dead) {
          addWeighted(out, k, misWeight(previousPdf, lightPdf, previousPdf, 0, 0), base, Rgb());
          continue;
        }
        const bool replay = o.mode == OffsetPath::Mode::Replay;
        const bool offsetFound = replay ? o.found : found;
        const SurfaceHit& offsetHit = replay ? o.hit : hit;
        const float offsetLightPdf =
            o.stepDelta ? 0 : lightPdfOf(offsetFound, offsetHit, o.previousPosition, o.incoming);
        const float scale = o.ratioBefore * o.stepJacobian;
        addWeighted(out, k, misWeight(previousPdf, lightPdf, previousPdf, scale * offsetLightPdf, scale * o.stepPdf),
                    base, o.throughput * arrivingEmission(offsetFound, offsetHit, o.incoming));
      }
    }
    if (!found || depth >= settings_.maxDepth) break;

    const BounceSamples u(stream);
    if (!vertexAhead) vertexAhead.emplace(scene, hit, ray.direction);
    const ShadedVertex vertex = *vertexAhead;
    vertexAhead.reset();
    const bool connectable = isConnectable(vertex.bsdf);
    // The offsets' own vertices: replayed ones at their own hit, reconnected ones at the
    // base's vertex, reached from their own direction at the first shared vertex and from
    // the base's after it, where they are the base's vertex itself.
    std::array<std::optional<ShadedVertex>, 4> ownVertex;
    std::array<const ShadedVertex*, 4> offsetVertex{};
    for (size_t k = 0; k < 4; ++k) {
      OffsetPath& o = offsets[k];
      if (o.mode == OffsetPath::Mode::Replay && !o.found) o.mode = OffsetPath::Mode::Dead;  // escaped earlier
      if (o.mode == OffsetPath::Mode::Replay) offsetVertex[k] = &ownVertex[k].emplace(scene, o.hit, o.incoming);
      if (o.mode == OffsetPath::Mode::Reconnected)
        offsetVertex[k] = o.firstShared ? &ownVertex[k].emplace(scene, hit, o.incoming) : &vertex;
    }

    // Next-event estimation towards the light point the base's random numbers choose.
    if (vertex.bsdf.hasNonDeltaLobe() && !lights_.empty()) {
      if (const auto light = lights_.sample(geometry_, vertex.hit.position, time, u.light, u.lightPoint)) {
        const Vec3f wi = vertex.frame.toLocal(light->direction);
        const Rgb f = vertex.bsdf.eval(vertex.wo, wi);
        // BSDF sampling never reaches a punctual light: its technique's density is 0.
        const float bsdfPdf = light->delta ? 0 : vertex.bsdf.pdf(vertex.wo, wi);
        bool visible = false;
        if (!f.isBlack()) {
          ++counts.shadow;
          visible =
              std::isinf(light->distance)
                  ? geometry_.escapes(vertex.hit, light->direction, time)
                  : geometry_.connects(vertex.hit, vertex.hit.position + light->direction * light->distance, time);
        }
        const Rgb base = visible ? throughput * f * light->radiance / light->pdf : Rgb();
        out.radiance += base * powerHeuristic(light->pdf, bsdfPdf);
        for (size_t k = 0; k < 4; ++k) {
          const OffsetPath& o = offsets[k];
          if (o.mode == OffsetPath::Mode::Dead) {
            addWeighted(out, k, misWeight(light->pdf, light->pdf, bsdfPdf, 0, 0), base, Rgb());
            continue;
          }
          const ShadedVertex& y = *offsetVertex[k];
          const bool sharesVertex = &y == &vertex;  // then its light sample, f and pdf are the base's
          // Light points depend on the random numbers alone: the offset aims at the same
          // point, so the step's Jacobian is the ratio of the solid-angle densities.
          const auto offsetLight = o.mode == OffsetPath::Mode::Replay
                                       ? lights_.sample(geometry_, y.hit.position, time, u.light, u.lightPoint)
                                       : light;
          if (!offsetLight || !y.bsdf.hasNonDeltaLobe()) {
            addWeighted(out, k, misWeight(light->pdf, light->pdf, bsdfPdf, 0, 0), base, Rgb());
            continue;
          }
          const Vec3f offsetWi = sharesVertex ? wi : y.frame.toLocal(offsetLight->direction);
          const Rgb offsetF = sharesVertex ? f : y.bsdf.eval(y.wo, offsetWi);
          const float jacobian = light->pdf / offsetLight->pdf;
          bool offsetVisible = visible;
          if (o.mode == OffsetPath::Mode::Replay && !offsetF.isBlack()) {
            ++counts.shadow;
            offsetVisible =
                std::isinf(offsetLight->distance)
                    ? geometry_.escapes(y.hit, offsetLight->direction, time)
                    : geometry_.connects(y.hit, y.hit.position + offsetLight->direction * offsetLight->distance, time);
          }
          const Rgb offset = offsetVisible ? o.throughput * offsetF * offsetLight->radiance / offsetLight->pdf : Rgb();
          const float scale = o.ratio * jacobian;
          addWeighted(
              out, k,
              misWeight(light->pdf, light->pdf, bsdfPdf, scale * offsetLight->pdf,
                        light->delta ? 0 : scale * (sharesVertex ? bsdfPdf : y.bsdf.pdf(y.wo, offsetWi))),
              base, offset);
        }
      }
    }

    const auto scattered = vertex.bsdf.sample(vertex.wo, u.lobe, u.direction);
    if (!scattered || scattered->weight.isBlack()) break;
    throughput *= scattered->weight;
    const Vec3f direction = normalize(vertex.frame.toWorld(scattered->wi));
    float survive = 1;
    if (depth + 1 >= settings_.rouletteDepth) {
      survive = std::min(1.0f, throughput.maxComponent());
      if (u.roulette >= survive) break;
      throughput *= 1.0f / survive;
    }
    const Ray next{offsetRayOrigin(vertex.hit, direction), direction};
    SurfaceHit nextHit;
    const bool nextFound = intersect(next, nextHit);
    if (nextFound) vertexAhead.emplace(scene, nextHit, direction);
    const bool nextConnectable = !nextFound || isConnectable(vertexAhead->bsdf);

    for (size_t k = 0; k < 4; ++k) {
      OffsetPath& o = offsets[k];
      if (o.mode == OffsetPath::Mode::Dead) continue;
      const ShadedVertex& y = *offsetVertex[k];
      o.ratioBefore = o.ratio;
      o.previousPosition = y.hit.position;
      if (o.mode == OffsetPath::Mode::Reconnected) {
        // The vertex is the base's: copy the direction. Only the first shared vertex sees
        // a different incoming direction; from the next one on the factors are the base's.
        if (o.firstShared) {
          const Rgb f = y.bsdf.eval(y.wo, scattered->wi);
          const float pdf = y.bsdf.pdf(y.wo, scattered->wi);
          o.throughput *= f / scattered->pdf;
          o.ratio *= pdf / scattered->pdf;
          o.stepPdf = pdf;
          o.firstShared = false;
        } else {
          o.throughput *= scattered->weight;
          o.stepPdf = scattered->pdf;
        }
        o.stepJacobian = 1;
        o.stepDelta = scattered->delta;
        o.incoming = direction;
      } else if (connectable && isConnectable(y.bsdf) && nextConnectable) {
        // Reconnect to the base's next vertex (or follow it out into the environment).
        std::optional<Reconnection> link = nextFound ? reconnect(y.hit.position, vertex.hit.position, nextHit)
                                                     : std::optional<Reconnection>(Reconnection{direction, 0, 1});
        ++counts.shadow;
        const bool open = link && (nextFound ? geometry_.connects(y.hit, nextHit.position, time)
                                             : geometry_.escapes(y.hit, direction, time));
        if (!open) {
          o.mode = OffsetPath::Mode::Dead;
          continue;
        }
        const Vec3f wi = y.frame.toLocal(link->direction);
        const Rgb f = y.bsdf.eval(y.wo, wi);
        const float pdf = y.bsdf.pdf(y.wo, wi);
        if (f.isBlack()) {
          o.mode = OffsetPath::Mode::Dead;
          continue;
        }
        o.throughput *= f * (link->jacobian / scattered->pdf);
        o.ratio *= pdf * link->jacobian / scattered->pdf;
        o.stepPdf = pdf;
        o.stepJacobian = link->jacobian;
        o.stepDelta = false;
        o.incoming = link->direction;
        o.mode = OffsetPath::Mode::Reconnected;
        o.firstShared = true;
      } else {
        // Replay the base's random numbers at the offset's own vertex. A discrete choice
        // must meet a discrete one: a delta lobe has no density to compare with a glossy one.
        const auto own = y.bsdf.sample(y.wo, u.lobe, u.direction);
        if (!own || own->weight.isBlack() || own->delta != scattered->delta) {
          o.mode = OffsetPath::Mode::Dead;
          continue;
        }
        o.throughput *= own->weight;
        o.stepPdf = own->pdf;
        o.stepJacobian = scattered->pdf / own->pdf;
        o.stepDelta = own->delta;
        o.incoming = normalize(y.frame.toWorld(own->wi));
        o.ray = {offsetRayOrigin(y.hit, o.incoming), o.incoming};
        o.found = intersect(o.ray, o.hit);
        // Invertibility: from a connectable pair, the shift back would reconnect to a
        // connectable replayed vertex, and so reach another base path. No shift, then.
        if (connectable && isConnectable(y.bsdf) &&
            (!o.found || isConnectable(ShadedVertex(scene, o.hit, o.incoming).bsdf))) {
          o.mode = OffsetPath::Mode::Dead;
          continue;
        }
      }
      if (survive < 1) {
        // The base's roulette decides for both; the offset, sampled on its own, would have
        // survived with its own probability.
        o.throughput *= 1.0f / survive;
        const float own = o.ratio > 0 ? std::min(1.0f, o.throughput.maxComponent() * survive / o.ratio) : 0;
        o.ratio *= own / survive;
        o.ratioBefore *= own / survive;
      }
    }
    ray = next;
    hit = nextHit;
    found = nextFound;
    previousPdf = scattered->pdf;
    previousDelta = scattered->delta;
    previousPosition = vertex.hit.position;
  }
  return out;
}

}  // namespace pathfarm
