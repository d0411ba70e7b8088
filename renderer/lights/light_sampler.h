#pragma once
// Next-event estimation: picks an emitter (area lights on any shape, and the environment,
// environment_light.h) in proportion to its power, then a point on it, and reports the
// density of that choice over solid angle so it can be combined with BSDF sampling by
// multiple importance sampling.
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
  float distance;   // to the light point; infinity for the environment
  Rgb radiance;     // arriving along -direction
  float pdf;        // solid angle, including the choice of the emitter
};

class LightSampler {
 public:
  explicit LightSampler(const ShotGeometry& shot);

  bool empty() const { return emitters_.empty() && environmentProbability_ == 0; }
  // uLight chooses the emitter (and the triangle), uPoint the point on it.
  std::optional<LightSample> sample(const FrameGeometry& frame, Vec3f from, float time,
                                    float uLight, Vec2f uPoint) const;
  // Density over solid angle with which sample() yields the emitter point `hit`, seen from `from`.
  float pdf(const FrameGeometry& frame, Vec3f from, const SurfaceHit& hit, float time) const;
  // Density over solid angle with which sample() yields the environment in `direction`.
  float environmentPdf(Vec3f direction) const;

  // For light subpaths: whether uLight chooses the environment rather than a surface
  // emitter (the same choice sample() makes), the direction sample() then takes from
  // uPoint, and the point sample() would take on the surface emitter uLight chooses
  // (nothing when it chooses the environment).
  bool choosesEnvironment(float uLight) const;
  std::optional<LightSample> sampleEnvironment(Vec2f uPoint) const;
  std::optional<EmitterPoint> sampleEmitterPoint(const FrameGeometry& frame, float time, float uLight,
                                                 Vec2f uPoint) const;
  // Area density with which sampleEmitterPoint() yields the emitter point `hit` (0 off emitters).
  float emitterPointPdf(const FrameGeometry& frame, const SurfaceHit& hit, float time) const;
  // The probability of choosing the environment (its share of the power).
  float environmentProbability() const { return environmentProbability_; }

 private:
  struct Emitter {
    int object;
    float probability;
    std::vector<float> triangleCdf;  // over the prepared shape's triangle areas
  };
  float pointDensity(const FrameGeometry& frame, const Emitter& emitter, uint32_t triangle,
                     float time) const;

  const ShotGeometry& shot_;
  std::vector<Emitter> emitters_;
  std::vector<float> emitterCdf_;
  std::vector<int> emitterOfObject_;  // -1 for objects that do not emit
  float environmentProbability_ = 0;
};

}  // namespace pathfarm
