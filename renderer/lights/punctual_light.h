#pragma once
// Punctual lights, as glTF's KHR_lights_punctual defines them: a point, a spot and a
// directional light, each placed by its own (possibly animated) transform and shining
// down its local -z axis. They have no area, so no ray ever hits them: they are reached
// by next-event estimation only, are invisible to the camera and in mirrors, and light
// seen through a specular chain from them (a caustic) is found only by the integrators
// that trace light subpaths (bdpt and the Metropolis ones).
//
// Units follow the scene's radiance, with no photometric conversion: a point or spot
// light's `intensity` is radiant intensity (radiance times area, per steradian), so a
// surface at distance d facing it receives intensity / d^2; a directional light's is the
// irradiance on a surface facing it.
#include <optional>
#include <string>

#include "renderer/math/vecmath.h"
#include "renderer/math/animation.h"

namespace pathfarm {

enum class PunctualType { Point, Spot, Directional };

struct PunctualEmission {
  Vec3f direction;  // unit, leaving the light
  Rgb intensity;    // along `direction`, the spot's falloff applied
  float pdf;        // solid angle
};

struct PunctualLight {
  std::string name;
  PunctualType type = PunctualType::Point;
  Rgb intensity;
  // Spot cone half-angles as cosines; light falls off smoothly (quadratically in the
  // cosine, as KHR_lights_punctual suggests) from the inner to the outer cone.
  float cosInner = 1, cosOuter = 0.70710678f;
  AnimatedTrs transform;  // light to world

  Vec3f position(double seconds) const { return transform.at(seconds).translation; }
  // The direction the light shines along (its local -z in world space).
  Vec3f forward(double seconds) const;
  // Intensity leaving the light in world direction `direction` (unit), when the light
  // points along `forward` (forward(seconds) at the time in question).
  Rgb intensityToward(Vec3f direction, Vec3f forward) const;
  // Total emitted power's luminance, for choosing among lights; directional lights
  // pour their irradiance over a disk of radius `sceneRadius`.
  float power(float sceneRadius) const;
  // A direction leaving a point or spot light, uniform over the sphere or the outer cone.
  std::optional<PunctualEmission> sampleEmission(Vec2f u, Vec3f forward) const;
  float emissionPdf(Vec3f direction, Vec3f forward) const;
};

}  // namespace pathfarm
