#include "renderer/integrators/path_tracer.h"

#include "renderer/integrators/path_vertex.h"
#include "renderer/math/sampling.h"

namespace pathfarm {

Rgb PathTracer::radiance(Ray ray, float time, SampleStream& stream, RayCounts& counts, PathRecord* record) const {
  const Scene& scene = geometry_.shot().scene();
  Rgb result, throughput(1.0f);
  bool specularBounce = true;  // the camera "sees" emitters with full weight
  float previousPdf = 0;
  Vec3f previousPosition;
  float pathLength = 0;
  PathDecomposer* const decomposer = record ? record->decomposer : nullptr;

  for (int depth = 0;; ++depth) {
    SurfaceHit hit;
    ++counts.closestHit;
    if (!geometry_.intersect(ray, time, hit)) {
      if (!scene.environment.isBlack()) {
        const Rgb sky = scene.environment.radiance(ray.direction);
        const float weight = specularBounce ? 1 : powerHeuristic(previousPdf, lights_.environmentPdf(ray.direction));
        result += throughput * sky * weight;
        if (decomposer) decomposer->addEmission(sky * weight);
      }
      break;
    }
    if (record && depth == 0) {
      record->hit = true;
      record->primary = hit;
    }
    pathLength += hit.distance;
    const SceneObject& object = scene.objects[static_cast<size_t>(hit.object)];
    const bool emitting = object.isEmitter() && dot(ray.direction, hit.geometricNormal) < 0;
    if (emitting) {
      const float weight = specularBounce
                               ? 1
                               : powerHeuristic(previousPdf, lights_.pdf(geometry_, previousPosition, hit, time));
      const Rgb emission = emissionAt(scene, object, hit.uv);
      result += throughput * emission * weight;
      if (decomposer) decomposer->addEmission(emission * weight);
    }
    if (depth >= settings_.maxDepth) break;

    const BounceSamples u(stream);
    const ShadedVertex shaded(scene, hit, ray.direction);
    hit = shaded.hit;
    const Vec3f normal = shaded.normal;
    const Frame& frame = shaded.frame;
    const Vec3f wo = shaded.wo;
    const Bsdf& bsdf = shaded.bsdf;
    const LobeList lobes = decomposer ? bsdf.lobes() : LobeList{};
    const bool animated = decomposer && object.moves();

    if (bsdf.hasNonDeltaLobe() && !lights_.empty()) {
      if (const auto light = lights_.sample(geometry_, hit.position, time, u.light, u.lightPoint)) {
        const Vec3f wi = frame.toLocal(light->direction);
        // The lobes sum to eval() exactly (lobe_interface.h), so the beauty keeps its bits.
        const LobeValues perLobe = decomposer ? bsdf.evalLobes(wo, wi) : LobeValues{};
        const Rgb f = decomposer ? perLobe.sum() : bsdf.eval(wo, wi);
        if (!f.isBlack()) {
          ++counts.shadow;
          const bool visible = std::isinf(light->distance)
                                   ? geometry_.escapes(hit, light->direction, time)
                                   : geometry_.connects(hit, hit.position + light->direction * light->distance, time);
          if (visible) {
            const float weight = light->delta ? 1 : powerHeuristic(light->pdf, bsdf.pdf(wo, wi));
            result += throughput * f * light->radiance * (weight / light->pdf);
            if (decomposer)
              decomposer->addLightSample(lobes, perLobe, light->radiance * (weight / light->pdf), animated);
          }
        }
      }
    }

    const auto scattered = bsdf.sample(wo, u.lobe, u.direction);
    if (decomposer) {
      const VertexFeatures vertex{hit.position, normal, hit.uv, pathLength,
                                  hit.object, object.objectId, hit.primitive, animated};
      decomposer->scatter(lobes, vertex, scattered ? &*scattered : nullptr);
    }
    if (!scattered || scattered->weight.isBlack()) break;
    throughput *= scattered->weight;
    specularBounce = scattered->delta;
    previousPdf = scattered->pdf;
    previousPosition = hit.position;
    const Vec3f direction = normalize(frame.toWorld(scattered->wi));
    ray = {offsetRayOrigin(hit, direction), direction};

    if (depth + 1 >= settings_.rouletteDepth) {
      const float survive = std::min(1.0f, throughput.maxComponent());
      if (u.roulette >= survive) break;
      throughput *= 1.0f / survive;
      if (decomposer) decomposer->scale(1.0f / survive);
    }
  }
  return result;
}

void PathTracer::traceFeatures(Ray ray, float time, SampleStream& stream, RayCounts& counts,
                               PathDecomposer& decomposer) const {
  const Scene& scene = geometry_.shot().scene();
  float pathLength = 0;
  for (int depth = 0; depth < settings_.maxDepth; ++depth) {
    SurfaceHit hit;
    ++counts.closestHit;
    if (!geometry_.intersect(ray, time, hit)) return;
    pathLength += hit.distance;
    const BounceSamples u(stream);
    const ShadedVertex shaded(scene, hit, ray.direction);
    const SceneObject& object = scene.objects[static_cast<size_t>(hit.object)];
    const LobeList lobes = shaded.bsdf.lobes();
    const auto scattered = shaded.bsdf.sample(shaded.wo, u.lobe, u.direction);
    const VertexFeatures vertex{shaded.hit.position, shaded.normal, shaded.hit.uv, pathLength,
                                hit.object, object.objectId, shaded.hit.primitive, object.moves()};
    decomposer.scatter(lobes, vertex, scattered ? &*scattered : nullptr);
    if (!scattered || scattered->weight.isBlack() || scattered->symbol == LobeSymbol::D) return;
    const Vec3f direction = normalize(shaded.frame.toWorld(scattered->wi));
    ray = {offsetRayOrigin(shaded.hit, direction), direction};
  }
}

}  // namespace pathfarm
