#pragma once
// A scene placed for one frame with everything bidirectional sampling needs.
#include "renderer/accel/embree_device.h"
#include "renderer/bidirectional/bdpt_scene.h"
#include "renderer/integrators/light_sampler.h"
#include "test_support.h"

namespace pathfarm::test_support {

struct BdptFixture {
  Scene scene;
  EmbreeDevice device;
  ShotGeometry shot;
  FrameGeometry frame;
  LightSampler lights;
  CameraImportance camera;

  BdptFixture(Scene loaded, int width, int height, int64_t frameIndex = 0)
      : scene(std::move(loaded)),
        shot(scene, device),
        frame(shot, frameIndex),
        lights(shot),
        camera(scene.camera, width, height) {}

  BdptScene bdpt(int maxDepth = 8) const { return {frame, lights, camera, maxDepth}; }
};

}  // namespace pathfarm::test_support
