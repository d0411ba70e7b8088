#pragma once
// Toy scenes for the path-space mutations: a few quads, a lamp, and either a moving
// mirror (specular chains by reflection) or a glass wedge (chains by refraction), with a
// moving camera and a moving quad; 1 frame per second, shutter open half of each frame.
#include <filesystem>
#include <fstream>
#include <string>

#include "test_support.h"

namespace pathfarm::test_support {

inline std::string toyScene(const std::string& specularShape) {
  return R"({
    "fps": 1,
    "camera": {"position": [0, 1, 5], "look_at": [0, 0.8, 0], "fov": 50, "shutter": [0, 0.5],
               "animation": {"translate": [{"frame": 0, "value": [-0.1, 1, 5]}, {"frame": 4, "value": [0.2, 1.1, 5]}]}},
    "materials": {"grey": {"type": "diffuse", "reflectance": 0.5},
                  "mirror": {"type": "conductor", "specular_color": 1},
                  "glass": {"type": "dielectric", "ior": 1.5},
                  "lamp": {"type": "diffuse", "reflectance": 0}},
    "shapes": [
      {"type": "rectangle", "size": [6, 6], "material": "grey", "transform": {"rotate": {"axis": [1, 0, 0], "angle": -90}}},
      {"type": "rectangle", "size": [6, 4], "material": "grey", "transform": {"translate": [0, 2, -2]}},
      {"type": "rectangle", "size": [0.8, 0.8], "material": "grey", "transform": {"rotate": {"axis": [0, 1, 0], "angle": -30}, "scale": [2, 1, 1]},
       "animation": {"translate": [{"frame": 0, "value": [0.9, 0.5, -0.5]}, {"frame": 4, "value": [1.3, 0.7, -0.2]}]}},
      {"type": "rectangle", "size": [1.2, 1.2], "material": "lamp", "emission": 12,
       "transform": {"translate": [0, 2.8, 0], "rotate": {"axis": [1, 0, 0], "angle": 90}}},
      )" + specularShape + R"(]
  })";
}

inline std::string movingMirrorScene() {
  return toyScene(R"({"type": "rectangle", "size": [1.6, 1.6], "material": "mirror",
       "transform": {"rotate": {"axis": [0, 1, 0], "angle": 40}},
       "animation": {"translate": [{"frame": 0, "value": [-1.3, 0.9, -0.6]}, {"frame": 4, "value": [-0.9, 1.1, -0.3]}]}})");
}

// A glass wedge (its mesh written to a folder of this test process's own, named by its
// absolute path): light enters its sloped face and leaves by its base, faces that are
// not parallel.
inline std::string glassWedgeScene() {
  const std::filesystem::path folder = processTemporaryFolder("pathfarm_path_space");
  std::ofstream(folder / "wedge.obj") << R"(
v -0.6 0 -0.6
v 0.6 0 -0.6
v -0.6 0.7 -0.6
v -0.6 0 0.6
v 0.6 0 0.6
v -0.6 0.7 0.6
f 1 3 2
f 4 5 6
f 1 2 5
f 1 5 4
f 1 4 6
f 1 6 3
f 2 3 6
f 2 6 5
)";
  return toyScene(R"({"type": "mesh", "file": ")" + (folder / "wedge.obj").string() + R"(", "material": "glass",
       "animation": {"translate": [{"frame": 0, "value": [-0.3, 0.9, 0]}, {"frame": 4, "value": [0.1, 1.0, 0.1]}]}})");
}

}  // namespace pathfarm::test_support
