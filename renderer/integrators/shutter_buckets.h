#pragma once
// A frame's shutter cut into kBuckets equal parts, with the camera's placement at the
// centre of each, made once per rendered window. A camera sample takes its bucket's time
// and placement instead of evaluating the camera's animation (a slerp and a matrix) at a
// time of its own, which cost about a tenth of a 64-spp render of an animated camera and
// more of the short samples of features (docs/performance.md). The shutter's integral
// becomes a midpoint rule over the buckets: within one, a camera that sweeps a frame's
// width per frame moves a tenth of a pixel at 320 pixels. The scene is intersected at the
// same bucketed time, so camera and objects stay in step.
#include <cstdint>
#include <vector>

#include "renderer/math/transform.h"
#include "renderer/scene/camera.h"
#include "renderer/scene/scene.h"

namespace pathfarm {

class ShutterBuckets {
 public:
  static constexpr int kBuckets = 1024;

  ShutterBuckets(const Scene& scene, const Camera& camera, int64_t frame);

  // The bucket of shutter fraction u in [0, 1) (clamped): the fraction of its centre.
  static float time(float u);
  // The camera's placement at time(u), as camera.cameraToWorld gives it.
  const Transform& cameraToWorld(float u) const { return placements_[static_cast<size_t>(bucketOf(u))]; }

 private:
  static int bucketOf(float u);
  std::vector<Transform> placements_;
};

}  // namespace pathfarm
