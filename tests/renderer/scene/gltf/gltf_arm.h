#pragma once
// A skinned arm for the character tests, written as a glTF file by GltfBuilder. It lies
// in the xy plane facing +z: the upper arm x in [0, 1] follows the shoulder joint (node
// 1, at the origin), the forearm x in [1, 2] the elbow joint (node 2, at x = 1, the
// shoulder's child). The two vertices at the elbow (x = 1) are weighted 0.3 : 0.1 to the
// elbow and the shoulder, which normalizes to 3 : 1. The elbow turns by 90 degrees about
// `axis` over the first second (LINEAR). The mesh's own node sits at x = 100, which
// skinning must ignore.
#include <cmath>

#include "renderer/math/vecmath.h"
#include "tests/renderer/scene/gltf/gltf_builder.h"

namespace pathfarm::gltftest {

// Rest positions of the arm's vertices: 0 (0,0), 1 (1,0), 2 (2,0), 3 (2,1), 4 (1,1), 5 (0,1).
inline GltfBuilder skinnedArm(Vec3f axis, bool animated = true) {
  GltfBuilder b;
  const int position =
      b.floats({0, 0, 0, 1, 0, 0, 2, 0, 0, 2, 1, 0, 1, 1, 0, 0, 1, 0}, "VEC3", true);
  const int normal = b.floats(std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
  // Joint 0 is the shoulder, joint 1 the elbow.
  const int joints = b.unsignedShorts({0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0}, "VEC4");
  const int weights = b.floats({1, 0, 0, 0, 0.3f, 0.1f, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0.3f, 0.1f, 0, 0, 1, 0, 0, 0}, "VEC4");
  const int mesh = b.mesh({{"POSITION", position}, {"NORMAL", normal}, {"JOINTS_0", joints}, {"WEIGHTS_0", weights}},
                          b.indices(std::vector<uint16_t>{0, 1, 4, 0, 4, 5, 1, 2, 3, 1, 3, 4}));
  const int arm = b.node({{"mesh", mesh}, {"skin", 0}, {"translation", {100, 0, 0}}});
  const int elbow = b.node({{"translation", {1, 0, 0}}});
  const int shoulder = b.node({{"children", {elbow}}});
  // Inverse bind matrices (column-major): the shoulder's is the identity, the elbow's
  // takes x = 1 to the origin.
  const int inverseBind = b.floats({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1,  //
                                    1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -1, 0, 0, 1},
                                   "MAT4");
  b.doc()["skins"] = {{{"joints", {shoulder, elbow}}, {"inverseBindMatrices", inverseBind}}};
  const float s = std::sin(0.25f * kPi);  // a quarter turn: sin and cos of half its angle
  if (animated) {
    const int times = b.floats({0, 1}, "SCALAR");
    const int turns = b.floats({0, 0, 0, 1, axis.x * s, axis.y * s, axis.z * s, s}, "VEC4");
    b.doc()["animations"] = {{{"samplers", {{{"input", times}, {"output", turns}, {"interpolation", "LINEAR"}}}},
                              {"channels", {{{"sampler", 0}, {"target", {{"node", elbow}, {"path", "rotation"}}}}}}}};
  } else {
    b.doc()["nodes"][static_cast<size_t>(elbow)]["rotation"] = {axis.x * s, axis.y * s, axis.z * s, s};
  }
  b.scene({arm, shoulder, b.camera({1, 0.5f, 4})});
  return b;
}

}  // namespace pathfarm::gltftest
