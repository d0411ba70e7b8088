#pragma once
// What every Metropolis target needs of a window: its time, its frames' geometry, the
// emitters, the camera as a sensor, the image size and the path length limit. Built
// once per window and only read by the chains.
#include "renderer/bidirectional/bdpt_scene.h"
#include "renderer/metropolis/window_geometry.h"
#include "renderer/metropolis/window_time.h"

namespace pathfarm {

struct WindowScene {
  const WindowTime& time;
  const WindowGeometry& geometry;
  const LightSampler& lights;
  const CameraImportance& camera;
  int maxDepth = 8;

  int width() const { return camera.width(); }
  int height() const { return camera.height(); }
  // Bidirectional sampling in one frame of the window.
  BdptScene frame(int64_t frame) const { return {geometry.frame(frame), lights, camera, maxDepth}; }
};

}  // namespace pathfarm
