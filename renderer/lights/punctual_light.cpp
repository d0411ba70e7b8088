#include "renderer/lights/punctual_light.h"

#include <algorithm>

#include "renderer/math/frame.h"
#include "renderer/math/sampling.h"

namespace pathfarm {
namespace {

// KHR_lights_punctual's suggested falloff: the square of a linear ramp in the cosine
// from the outer cone (0) to the inner one (1).
float spotFalloff(float cosAngle, float cosInner, float cosOuter) {
  const float t = std::clamp((cosAngle - cosOuter) / std::max(cosInner - cosOuter, 1e-3f), 0.0f, 1.0f);
  return t * t;
}

}  // namespace

Vec3f PunctualLight::forward(double seconds) const {
  return normalize(transform.at(seconds).rotation.rotate({0, 0, -1}));
}

Rgb PunctualLight::intensityToward(Vec3f direction, Vec3f forward) const {
  if (type != PunctualType::Spot) return intensity;
  return intensity * spotFalloff(dot(direction, forward), cosInner, cosOuter);
}

float PunctualLight::power(float sceneRadius) const {
  const float luminance = intensity.luminance();
  switch (type) {
    case PunctualType::Point:
      return 4 * kPi * luminance;
    case PunctualType::Spot:
      // 2 pi times the falloff integrated over the cosine: 1 inside the inner cone, a
      // third of the ramp's width between the cones.
      return 2 * kPi * luminance * ((1 - cosInner) + (cosInner - cosOuter) / 3);
    case PunctualType::Directional:
      return kPi * sceneRadius * sceneRadius * luminance;
  }
  return 0;
}

std::optional<PunctualEmission> PunctualLight::sampleEmission(Vec2f u, Vec3f forward) const {
  if (type == PunctualType::Directional) return std::nullopt;
  PunctualEmission e;
  if (type == PunctualType::Point) {
    e.direction = sampleUniformSphere(u);
    e.pdf = kUniformSpherePdf;
  } else {
    e.direction = normalize(Frame::fromNormal(forward).toWorld(sampleUniformCone(u, cosOuter)));
    e.pdf = uniformConePdf(cosOuter);
  }
  e.intensity = intensityToward(e.direction, forward);
  if (e.intensity.isBlack()) return std::nullopt;
  return e;
}

float PunctualLight::emissionPdf(Vec3f direction, Vec3f forward) const {
  switch (type) {
    case PunctualType::Point:
      return kUniformSpherePdf;
    case PunctualType::Spot:
      return dot(direction, forward) >= cosOuter ? uniformConePdf(cosOuter) : 0;
    case PunctualType::Directional:
      return 0;
  }
  return 0;
}

}  // namespace pathfarm
