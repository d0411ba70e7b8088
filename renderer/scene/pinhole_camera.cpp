#include "renderer/scene/pinhole_camera.h"

namespace pathfarm {

PinholeCamera::PinholeCamera(const CameraDesc& desc, int width, int height)
    : desc_(desc),
      animated_(desc.transform.isAnimated()),
      still_(desc.transform.motionAt(0)),
      tanHalfFov_(std::tan(0.5 * desc.fovDegrees * 3.14159265358979323846 / 180.0)),
      aspect_(static_cast<double>(width) / height),
      width_(width),
      height_(height) {}

PinholeCamera::Placed::Placed(const PinholeCamera& camera, const AffineMotion& toWorld)
    : camera_(camera), toWorld_(toWorld), toCamera_(toWorld.linear.inverse()) {}

Vec3d PinholeCamera::Placed::direction(Vec2d film) const {
  const PinholeCamera& c = camera_;
  const Vec3d local{(2 * film.x / c.width_ - 1) * c.tanHalfFov_ * c.aspect_, (1 - 2 * film.y / c.height_) * c.tanHalfFov_,
                    -1};
  return normalize(toWorld_.vector(local));
}

std::optional<Vec2d> PinholeCamera::Placed::project(Vec3d point) const {
  const PinholeCamera& c = camera_;
  const Vec3d v = toCamera_ * (point - toWorld_.translation);
  if (!(v.z < 0)) return std::nullopt;  // behind the camera, or not a number
  return Vec2d{(v.x / -v.z / (c.tanHalfFov_ * c.aspect_) + 1) * 0.5 * c.width_,
               (1 - v.y / -v.z / c.tanHalfFov_) * 0.5 * c.height_};
}

}  // namespace pathfarm
