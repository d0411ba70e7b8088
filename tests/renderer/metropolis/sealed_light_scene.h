#pragma once
// A scene whose light cannot reach the camera: the lamp shines inside a closed sphere that
// the camera sees from outside. Every Metropolis method must give black, finite frames.
#include "renderer/scene/scene.h"
#include "test_support.h"

namespace pathfarm::test_support {

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
