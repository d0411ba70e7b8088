#pragma once
// Screen-space motion of what a pixel sees: the visible point's object-space position
// carried to a neighbouring frame's object transform and projected with that frame's
// camera, at the same point of the shutter (Zimmer et al. 2015, Section 4). The
// background moves with the camera alone.
#include <optional>

#include "renderer/accel/frame_geometry.h"
#include "renderer/scene/camera.h"

namespace pathfarm {

class PrimaryMotion {
 public:
  PrimaryMotion(const FrameGeometry& geometry, const Camera& camera, int64_t frame)
      : geometry_(geometry), camera_(camera), frame_(frame) {}

  // Pixels moved by the point `hit` saw at shutter time `time` between this frame and
  // frame + `offset`; nothing if either image is behind the camera.
  std::optional<Vec2f> ofSurface(const SurfaceHit& hit, float time, int offset) const;
  // Likewise for the environment seen along `direction`.
  std::optional<Vec2f> ofBackground(Vec3f direction, float time, int offset) const;

 private:
  static std::optional<Vec2f> difference(const std::optional<Vec2f>& from, const std::optional<Vec2f>& to);
  const FrameGeometry& geometry_;
  const Camera& camera_;
  int64_t frame_;
};

}  // namespace pathfarm
