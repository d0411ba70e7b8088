#pragma once
// The camera's pinhole model (Camera's projection, the centre of a thin lens's blur) in
// double precision, moving with its animation: film positions to rays and back, for the
// specular manifold walk, whose motion vectors are differences of film positions.
#include <optional>

#include "renderer/math/vec3d.h"
#include "renderer/scene/camera.h"

namespace pathfarm {

class PinholeCamera {
 public:
  PinholeCamera(const CameraDesc& desc, int width, int height);

  bool isAnimated() const { return animated_; }
  // The pinhole at `seconds` and its velocity.
  Vec3d position(double seconds) const { return desc_.transform.motionAt(seconds).translation; }
  Vec3d velocity(double seconds) const { return desc_.transform.motionAt(seconds).translationRate; }
  // The unit direction of the ray through continuous pixel position `film` (x right,
  // y down, as Camera::generateRay).
  Vec3d direction(Vec2d film, double seconds) const;
  // Where `point` is imaged; nothing when it is not in front of the camera.
  std::optional<Vec2d> project(Vec3d point, double seconds) const;

 private:
  const CameraDesc& desc_;
  bool animated_;
  double tanHalfFov_, aspect_, width_, height_;
};

}  // namespace pathfarm
