#include "renderer/scene/pinhole_camera.h"

namespace pathfarm {

PinholeCamera::PinholeCamera(const CameraDesc& desc, int width, int height)
    : desc_(desc),
      animated_(desc.transform.isAnimated()),
      tanHalfFov_(std::tan(0.5 * desc.fovDegrees * 3.14159265358979323846 / 180.0)),
      aspect_(static_cast<double>(width) / height),
      width_(width),
      height_(height) {}

Vec3d PinholeCamera::direction(Vec2d film, double seconds) const {
  const Vec3d local{(2 * film.x / width_ - 1) * tanHalfFov_ * aspect_, (1 - 2 * film.y / height_) * tanHalfFov_, -1};
  return normalize(desc_.transform.motionAt(seconds).vector(local));
}

std::optional<Vec2d> PinholeCamera::project(Vec3d point, double seconds) const {
  const AffineMotion toWorld = desc_.transform.motionAt(seconds);
  const Vec3d v = toWorld.linear.inverse() * (point - toWorld.translation);
  if (!(v.z < 0)) return std::nullopt;  // behind the camera, or not a number
  return Vec2d{(v.x / -v.z / (tanHalfFov_ * aspect_) + 1) * 0.5 * width_,
               (1 - v.y / -v.z / tanHalfFov_) * 0.5 * height_};
}

}  // namespace pathfarm
