#pragma once
// Screen-space motion of what a pixel sees: the visible point's object-space position
// carried to a neighbouring frame's object transform and projected with that frame's
// camera, at the same point of the shutter (Zimmer et al. 2015, Section 4). The
// background moves with the camera alone.
#include <optional>

#include "renderer/accel/frame_geometry.h"
#include "renderer/scene/camera.h"

namespace pathfarm {

// Pixels moved to the next and from the previous frame; nothing where the point's image
// is behind the camera in one of them.
struct MotionPair {
  std::optional<Vec2f> forward, backward;
};

class PrimaryMotion {
 public:
  PrimaryMotion(const FrameGeometry& geometry, const Camera& camera, int64_t frame)
      : geometry_(geometry), camera_(camera), frame_(frame) {}

  // The point `hit` saw at shutter time `time`.
  MotionPair ofSurface(const SurfaceHit& hit, float time) const;
  // The environment seen along `direction`.
  MotionPair ofBackground(Vec3f direction, float time) const;

 private:
  const FrameGeometry& geometry_;
  const Camera& camera_;
  int64_t frame_;
};

}  // namespace pathfarm
