#pragma once
// Next-event estimation: picks an emitter (area lights on any shape, and the constant
// environment) in proportion to its power, then a point on it, and reports the
// density of that choice over solid angle so it can be combined with BSDF sampling by
// multiple importance sampling.
#include <optional>
#include <vector>

#include "renderer/accel/frame_geometry.h"

namespace pathfarm {

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
  float environmentPdf() const;

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
