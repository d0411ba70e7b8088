#include "client/keyframe_probe.h"

#include <gtest/gtest.h>

#include "test_support.h"

namespace pathfarm::farm {
namespace {

// A camera trucking over a lit floor below an open sky: the sky fills the top half of
// every frame and moves with nothing, and the interpolate task takes it from each
// in-between frame's own render instead of interpolating it. The probe must predict that
// too: counting the sky as light it cannot move (as it did, 55 % on the suite's dolly
// against a measured 15 %) it would refuse every interval.
TEST(KeyframeProbe, DirectlySeenSkyIsTakenFromTheFrameAsTheInterpolateTaskTakesIt) {
  const Scene scene = test_support::sceneFromJson(R"({
    "fps": 24,
    "camera": {"position": [-0.3, 0.8, 4], "look_at": [-0.3, 0.8, 0], "fov": 50,
               "animation": {"translate": [{"frame": 0, "value": [-0.3, 0.8, 4]},
                                           {"frame": 8, "value": [0.3, 0.8, 4]}]}},
    "materials": {"floor": {"type": "diffuse", "reflectance": 0.6},
                  "block": {"type": "diffuse", "reflectance": [0.7, 0.3, 0.2]}},
    "environment": {"radiance": [0.4, 0.5, 0.7]},
    "shapes": [
      {"type": "rectangle", "size": [40, 40], "material": "floor", "transform": {"rotate": {"axis": [1, 0, 0], "angle": -90}}},
      {"type": "box", "size": [0.6, 0.6, 0.6], "material": "block", "transform": {"translate": [0, 0.3, 0]}},
      {"type": "rectangle", "size": [1, 1], "material": "floor", "emission": 6,
       "transform": {"translate": [0, 3, 1], "rotate": {"axis": [1, 0, 0], "angle": 90}}}]
  })");
  ShotSpec spec;
  spec.set_frame_start(0);
  spec.set_frame_end(8);
  spec.set_width(256);
  spec.set_height(144);
  spec.set_max_depth(4);
  spec.set_decompose("diffuse_direct=ED,diffuse_indirect=ED.+,residual");
  const KeyframeChoice choice = chooseKeyframeInterval(scene, spec, 0.25, 4);
  EXPECT_GE(choice.interval, 2) << choice.reason;
  EXPECT_NE(choice.reason.find("the largest interval whose predicted re-render rate stays under 25.0%"),
            std::string::npos)
      << choice.reason;
}

}  // namespace
}  // namespace pathfarm::farm
