#pragma once
// What bidirectional sampling needs of the scene during one frame: geometry placed for
// the frame's shutter, the emitters, the camera as a sensor, and the path length limit.
// Every function taking a BdptScene also takes `time`, the path's shutter fraction in
// [0, 1]: one path lives at one time.
#include "renderer/accel/frame_geometry.h"
#include "renderer/bidirectional/camera_importance.h"
#include "renderer/integrators/light_sampler.h"

namespace pathfarm {

struct BdptScene {
  const FrameGeometry& geometry;
  const LightSampler& lights;
  const CameraImportance& camera;
  int maxDepth = 8;  // scattering events per path, as PathTracerSettings::maxDepth

  const Scene& scene() const { return geometry.shot().scene(); }
  double seconds(float time) const { return scene().timeAt(geometry.frame(), time); }
};

}  // namespace pathfarm
