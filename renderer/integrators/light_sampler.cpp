#include "renderer/integrators/light_sampler.h"

#include <algorithm>
#include <limits>

#include "renderer/math/sampling.h"

namespace pathfarm {
namespace {

float triangleArea(Vec3f a, Vec3f b, Vec3f c) { return 0.5f * length(cross(b - a, c - a)); }

// Cumulative triangle areas of a prepared shape.
std::vector<float> triangleCdf(const TriangleMesh& mesh) {
  std::vector<float> cdf;
  float total = 0;
  for (size_t t = 0; t < mesh.triangleCount(); ++t) {
    total += triangleArea(mesh.positions[mesh.indices[3 * t]], mesh.positions[mesh.indices[3 * t + 1]],
                          mesh.positions[mesh.indices[3 * t + 2]]);
    cdf.push_back(total);
  }
  return cdf;
}

// Surface area in world space at the start of the shot, for choosing among emitters.
float worldArea(const SceneObject& object, const PreparedShape& shape) {
  const Transform toWorld = shape.animated ? object.transform.transformAt(0) : shape.placement;
  if (shape.type == ShapeType::Sphere) {
    const float r = shape.radius * length(toWorld.vector({1, 0, 0}));
    return 4 * kPi * r * r;
  }
  float area = 0;
  const TriangleMesh& m = *shape.mesh;
  for (size_t t = 0; t < m.triangleCount(); ++t) {
    area += triangleArea(toWorld.point(m.positions[m.indices[3 * t]]),
                         toWorld.point(m.positions[m.indices[3 * t + 1]]),
                         toWorld.point(m.positions[m.indices[3 * t + 2]]));
  }
  return area;
}

// Radius of a sphere around every static shape, for the environment's share of power.
float sceneRadius(const ShotGeometry& shot) {
  const RTCBounds& b = shot.staticBounds();
  if (!(b.lower_x <= b.upper_x)) return 1;  // nothing static
  const Vec3f extent{b.upper_x - b.lower_x, b.upper_y - b.lower_y, b.upper_z - b.lower_z};
  return std::max(0.5f * length(extent), 1e-3f);
}

}  // namespace

LightSampler::LightSampler(const ShotGeometry& shot)
    : shot_(shot), emitterOfObject_(shot.scene().objects.size(), -1) {
  const Scene& scene = shot.scene();
  std::vector<float> power;
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const SceneObject& object = scene.objects[i];
    if (!object.isEmitter()) continue;
    const PreparedShape& shape = shot.shape(static_cast<int>(i));
    Emitter emitter{static_cast<int>(i), 0, {}};
    if (shape.type != ShapeType::Sphere) emitter.triangleCdf = triangleCdf(*shape.mesh);
    emitterOfObject_[i] = static_cast<int>(emitters_.size());
    emitters_.push_back(std::move(emitter));
    // A textured emitter by its mean radiance; points on it are still chosen by area.
    const Rgb meanEmission = object.emissionTexture < 0
                                 ? object.emission
                                 : object.emission * scene.textures[static_cast<size_t>(object.emissionTexture)].average();
    power.push_back(meanEmission.luminance() * kPi * worldArea(object, shape));
  }
  const bool needsRadius = !scene.environment.isBlack() ||
                           std::any_of(scene.punctualLights.begin(), scene.punctualLights.end(),
                                       [](const PunctualLight& l) { return l.type == PunctualType::Directional; });
  const float radius = needsRadius ? sceneRadius(shot) : 1;
  for (const PunctualLight& light : scene.punctualLights) power.push_back(light.power(radius));
  // Power an environment pours onto the scene's bounding sphere's cross-section.
  if (!scene.environment.isBlack()) power.push_back(scene.environment.meanLuminance() * kPi * kPi * radius * radius);

  float total = 0;
  for (float p : power) total += p;
  float running = 0;
  for (size_t i = 0; i < power.size(); ++i) {
    running += power[i];
    const float probability = total > 0 ? power[i] / total : 0;
    cdf_.push_back(total > 0 ? running / total : 0);
    if (i < emitters_.size()) {
      emitters_[i].probability = probability;
    } else if (i < emitters_.size() + scene.punctualLights.size()) {
      punctualProbability_.push_back(probability);
    } else {
      environmentProbability_ = probability;
    }
  }
}

LightChoice LightSampler::choose(float uLight) const {
  if (empty()) return {};
  const size_t i = std::min<size_t>(std::upper_bound(cdf_.begin(), cdf_.end(), uLight) - cdf_.begin(), cdf_.size() - 1);
  const float low = i == 0 ? 0 : cdf_[i - 1];
  LightChoice choice;
  const size_t punctualEnd = emitters_.size() + punctualProbability_.size();
  float probability;
  if (i < emitters_.size()) {
    choice.kind = LightChoice::Kind::Emitter;
    choice.index = static_cast<int>(i);
    probability = emitters_[i].probability;
  } else if (i < punctualEnd) {
    choice.kind = LightChoice::Kind::Punctual;
    choice.index = static_cast<int>(i - emitters_.size());
    probability = punctualProbability_[static_cast<size_t>(choice.index)];
  } else {
    choice.kind = LightChoice::Kind::Environment;
    probability = environmentProbability_;
  }
  choice.remainder = std::min((uLight - low) / probability, 0x1.fffffep-1f);
  return choice;
}

float LightSampler::environmentPdf(Vec3f direction) const {
  return environmentProbability_ * shot_.scene().environment.pdf(direction);
}

float LightSampler::pointDensity(const FrameGeometry& frame, const Emitter& emitter,
                                 uint32_t triangle, float time) const {
  const PreparedShape& shape = shot_.shape(emitter.object);
  const Transform toWorld = frame.shapeToWorld(emitter.object, time);
  if (shape.type == ShapeType::Sphere) {
    const float r = shape.radius * length(toWorld.vector({1, 0, 0}));
    return 1.0f / (4 * kPi * r * r);
  }
  // The triangle is chosen by its prepared-space area, then a point uniformly on its
  // world-space image: exact even when the transform scales unevenly.
  const TriangleMesh& m = *shape.mesh;
  const float before = triangle == 0 ? 0 : emitter.triangleCdf[triangle - 1];
  const float choice = (emitter.triangleCdf[triangle] - before) / emitter.triangleCdf.back();
  const float area = triangleArea(toWorld.point(m.positions[m.indices[3 * triangle]]),
                                  toWorld.point(m.positions[m.indices[3 * triangle + 1]]),
                                  toWorld.point(m.positions[m.indices[3 * triangle + 2]]));
  return area > 0 ? choice / area : 0;
}

std::optional<EmitterPoint> LightSampler::sampleEmitterPoint(const FrameGeometry& frame, float time, float uLight,
                                                             Vec2f uPoint) const {
  const LightChoice choice = choose(uLight);
  if (choice.kind != LightChoice::Kind::Emitter) return std::nullopt;
  const Emitter& emitter = emitters_[static_cast<size_t>(choice.index)];
  const PreparedShape& shape = shot_.shape(emitter.object);
  const Transform toWorld = frame.shapeToWorld(emitter.object, time);

  SurfaceHit hit;
  hit.object = emitter.object;
  if (shape.type == ShapeType::Sphere) {
    const Vec3f n = sampleUniformSphere(uPoint);
    hit.position = toWorld.point(shape.center + n * shape.radius);
    hit.geometricNormal = normalize(toWorld.normal(n));
    hit.uv = sphereUv(n);  // as a ray hitting it would find, for textured emission
  } else {
    // Reuse what is left of uLight inside the chosen emitter's interval to pick a triangle.
    const float u = choice.remainder * emitter.triangleCdf.back();
    hit.primitive = static_cast<uint32_t>(
        std::min<size_t>(std::upper_bound(emitter.triangleCdf.begin(), emitter.triangleCdf.end(), u) -
                             emitter.triangleCdf.begin(),
                         emitter.triangleCdf.size() - 1));
    const TriangleMesh& m = *shape.mesh;
    const Vec3f q0 = m.positions[m.indices[3 * hit.primitive]], q1 = m.positions[m.indices[3 * hit.primitive + 1]],
                q2 = m.positions[m.indices[3 * hit.primitive + 2]];
    const Vec2f b = sampleUniformTriangle(uPoint);
    hit.position = toWorld.point(q0 * (1 - b.x - b.y) + q1 * b.x + q2 * b.y);
    // As FrameGeometry's hits have it: the prepared triangle's normal carried to world
    // space, so that a mirroring placement keeps the emitting side.
    hit.geometricNormal = normalize(toWorld.normal(cross(q1 - q0, q2 - q0)));
    hit.uv = b;  // as a ray hitting it would find, for textured emission
    if (!m.uvs.empty()) {
      const Vec2f t0 = m.uvs[m.indices[3 * hit.primitive]], t1 = m.uvs[m.indices[3 * hit.primitive + 1]],
                  t2 = m.uvs[m.indices[3 * hit.primitive + 2]];
      const float b0 = 1 - b.x - b.y;
      hit.uv = {t0.x * b0 + t1.x * b.x + t2.x * b.y, t0.y * b0 + t1.y * b.x + t2.y * b.y};
    }
  }
  hit.shadingNormal = hit.geometricNormal;
  const float pdfArea = emitter.probability * pointDensity(frame, emitter, hit.primitive, time);
  if (!(pdfArea > 0) || !std::isfinite(pdfArea)) return std::nullopt;
  const Scene& scene = shot_.scene();
  return EmitterPoint{hit, emissionAt(scene, scene.objects[static_cast<size_t>(emitter.object)], hit.uv), pdfArea};
}

std::optional<LightSample> LightSampler::sample(const FrameGeometry& frame, Vec3f from, float time,
                                                float uLight, Vec2f uPoint) const {
  const LightChoice choice = choose(uLight);
  if (choice.kind == LightChoice::Kind::Environment) return sampleEnvironment(uPoint);
  if (choice.kind == LightChoice::Kind::Punctual)
    return samplePunctual(choice.index, from, shot_.scene().timeAt(frame.frame(), time));
  const auto point = sampleEmitterPoint(frame, time, uLight, uPoint);
  if (!point) return std::nullopt;
  const Vec3f toLight = point->hit.position - from;
  const float distance = length(toLight);
  if (distance <= 0) return std::nullopt;
  const Vec3f direction = toLight / distance;
  const float cosLight = -dot(point->hit.geometricNormal, direction);
  if (cosLight <= 0) return std::nullopt;  // the back of an emitter is dark
  const float pdf = point->pdfArea * distance * distance / cosLight;
  if (!(pdf > 0) || !std::isfinite(pdf)) return std::nullopt;
  return LightSample{direction, distance, point->radiance, pdf};
}

std::optional<LightSample> LightSampler::sampleEnvironment(Vec2f uPoint) const {
  if (environmentProbability_ == 0) return std::nullopt;
  const auto s = shot_.scene().environment.sample(uPoint);
  if (!s) return std::nullopt;
  return LightSample{s->direction, std::numeric_limits<float>::infinity(), s->radiance,
                     environmentProbability_ * s->pdf};
}

std::optional<LightSample> LightSampler::samplePunctual(int index, Vec3f from, double seconds) const {
  const PunctualLight& light = shot_.scene().punctualLights[static_cast<size_t>(index)];
  const float probability = punctualProbability(index);
  if (!(probability > 0)) return std::nullopt;
  if (light.type == PunctualType::Directional) {
    return LightSample{-light.forward(seconds), std::numeric_limits<float>::infinity(), light.intensity,
                       probability, true};
  }
  const Vec3f toLight = light.position(seconds) - from;
  const float distance = length(toLight);
  if (!(distance > 0)) return std::nullopt;
  const Vec3f direction = toLight / distance;
  const Rgb irradiance = light.intensityToward(-direction, light.forward(seconds)) / (distance * distance);
  if (irradiance.isBlack() || !irradiance.isFinite()) return std::nullopt;
  return LightSample{direction, distance, irradiance, probability, true};
}

float LightSampler::emitterPointPdf(const FrameGeometry& frame, const SurfaceHit& hit, float time) const {
  const int index = emitterOfObject_[static_cast<size_t>(hit.object)];
  if (index < 0) return 0;
  const Emitter& emitter = emitters_[static_cast<size_t>(index)];
  return emitter.probability * pointDensity(frame, emitter, hit.primitive, time);
}

float LightSampler::pdf(const FrameGeometry& frame, Vec3f from, const SurfaceHit& hit, float time) const {
  const Vec3f toLight = hit.position - from;
  const float distanceSquared = dot(toLight, toLight);
  const float cosLight = std::abs(dot(hit.geometricNormal, toLight)) / std::sqrt(distanceSquared);
  if (cosLight <= 0) return 0;
  return emitterPointPdf(frame, hit, time) * distanceSquared / cosLight;
}

}  // namespace pathfarm
