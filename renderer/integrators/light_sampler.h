#pragma once
// Next-event estimation: picks an emitter (area lights on any shape, punctual lights,
// punctual_light.h, and the environment, environment_light.h) in proportion to its power,
// then a point on it, and reports the density of that choice over solid angle so it can
// be combined with BSDF sampling by multiple importance sampling. Punctual lights are
// delta lights: their samples carry the probability of the choice, not a density, and
// only light sampling reaches them.
#include <optional>
#include <vector>

#include "renderer/accel/frame_geometry.h"

namespace pathfarm {

// A point on a surface emitter, for paths that start at the light (bidirectional path
// tracing): hit.position, hit.geometricNormal (the emitting side), hit.object and
// hit.primitive (the triangle) are set.
struct EmitterPoint {
  SurfaceHit hit;
  Rgb radiance;    // emitted from the front side
  float pdfArea;   // area density, including the choice of the emitter
};

struct LightSample {
  Vec3f direction;  // unit, from the shading point to the light
  float distance;   // to the light point; infinity for the environment and directional lights
  Rgb radiance;     // arriving along -direction; for a punctual light, the irradiance it
                    // gives a surface facing it
  float pdf;        // solid angle, including the choice of the emitter; for a punctual
                    // light, the probability of choosing it
  bool delta = false;  // a punctual light: BSDF sampling cannot reach it (MIS weight 1)
};

// Which light a number uLight in [0, 1) chooses, and what is left of it, rescaled to
// [0, 1), inside the chosen light's share.
struct LightChoice {
  enum class Kind { Emitter, Punctual, Environment, None } kind = Kind::None;
  int index = -1;  // into the emitters (sampleEmitterPoint) or Scene::punctualLights
  float remainder = 0;
};

class LightSampler {
 public:
  explicit LightSampler(const ShotGeometry& shot);

  bool empty() const { return cdf_.empty() || cdf_.back() == 0; }
  // uLight chooses the emitter (and the triangle), uPoint the point on it.
  std::optional<LightSample> sample(const FrameGeometry& frame, Vec3f from, float time,
                                    float uLight, Vec2f uPoint) const;
  // Density over solid angle with which sample() yields the emitter point `hit`, seen from `from`.
  float pdf(const FrameGeometry& frame, Vec3f from, const SurfaceHit& hit, float time) const;
  // Density over solid angle with which sample() yields the environment in `direction`.
  float environmentPdf(Vec3f direction) const;

  // For light subpaths: the light uLight chooses (the same choice sample() makes), the
  // direction sample() then takes from uPoint on the environment, and the point sample()
  // would take on the surface emitter uLight chooses (nothing when it chooses another kind).
  LightChoice choose(float uLight) const;
  std::optional<LightSample> sampleEnvironment(Vec2f uPoint) const;
  std::optional<EmitterPoint> sampleEmitterPoint(const FrameGeometry& frame, float time, float uLight,
                                                 Vec2f uPoint) const;
  // Area density with which sampleEmitterPoint() yields the emitter point `hit` (0 off emitters).
  float emitterPointPdf(const FrameGeometry& frame, const SurfaceHit& hit, float time) const;
  // The probability of choosing the environment (its share of the power).
  float environmentProbability() const { return environmentProbability_; }
  // The probability of choosing punctual light `light` (an index into Scene::punctualLights).
  float punctualProbability(int light) const { return punctualProbability_[static_cast<size_t>(light)]; }

 private:
  struct Emitter {
    int object;
    float probability;
    std::vector<float> triangleCdf;  // over the prepared shape's triangle areas
  };
  float pointDensity(const FrameGeometry& frame, const Emitter& emitter, uint32_t triangle,
                     float time) const;

  std::optional<LightSample> samplePunctual(int light, Vec3f from, double seconds) const;

  const ShotGeometry& shot_;
  std::vector<Emitter> emitters_;
  std::vector<int> emitterOfObject_;  // -1 for objects that do not emit
  std::vector<float> punctualProbability_;
  float environmentProbability_ = 0;
  // Cumulative probabilities over the surface emitters, then the punctual lights, then
  // the environment (when there is one).
  std::vector<float> cdf_;
};

}  // namespace pathfarm
