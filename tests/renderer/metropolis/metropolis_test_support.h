#pragma once
// What the Metropolis render tests share: small, fast settings and a scene whose light
// cannot reach the camera.
#include "renderer/metropolis/metropolis_renderer.h"
#include "renderer/scene/scene.h"
#include "test_support.h"

namespace pathfarm::test_support {

constexpr int kMetropolisTestSize = 24;

// 24x24 pixels, depth 4, 4000 bootstrap samples, 32 chains in blocks of 8, D = 0.5 frame
// (shorter than the closed half of a frame: frames are joined by renewed times).
inline MetropolisSettings smallMetropolisSettings(MetropolisMethod method, double mutationsPerPixel) {
  MetropolisSettings settings;
  settings.method = method;
  settings.width = settings.height = kMetropolisTestSize;
  settings.maxDepth = 4;
  settings.mutationsPerPixel = mutationsPerPixel;
  settings.bootstrapSamples = 4000;
  settings.chains = 32;
  settings.chainsPerBlock = 8;
  settings.temporalDelta = 0.5;
  return settings;
}

// The lamp shines inside a closed sphere that the camera sees from outside: every
// Metropolis method must give black, finite frames.
inline Scene sealedLightScene() {
  return sceneFromJson(R"({
    "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "shutter": [0, 0.5]},
    "materials": {"white": {"type": "diffuse", "reflectance": 0.7}},
    "shapes": [
      {"type": "sphere", "radius": 1, "material": "white"},
      {"type": "rectangle", "size": [0.3, 0.3], "material": "white", "emission": 10}]
  })");
}

}  // namespace pathfarm::test_support
