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

  // The camera at one time: evaluating the animation once serves many rays.
  class Placed {
   public:
    Vec3d position() const { return toWorld_.translation; }
    Vec3d velocity() const { return toWorld_.translationRate; }
    // The unit direction of the ray through continuous pixel position `film` (x right,
    // y down, as Camera::generateRay).
    Vec3d direction(Vec2d film) const;
    // Where `point` is imaged; nothing when it is not in front of the camera.
    std::optional<Vec2d> project(Vec3d point) const;

   private:
    friend class PinholeCamera;
    Placed(const PinholeCamera& camera, const AffineMotion& toWorld);
    const PinholeCamera& camera_;
    AffineMotion toWorld_;
    Mat3d toCamera_;
  };

  bool isAnimated() const { return animated_; }
  Placed at(double seconds) const { return {*this, animated_ ? desc_.transform.motionAt(seconds) : still_}; }

 private:
  const CameraDesc& desc_;
  bool animated_;
  AffineMotion still_;  // the placement of a camera that does not move
  double tanHalfFov_, aspect_, width_, height_;
};

}  // namespace pathfarm
