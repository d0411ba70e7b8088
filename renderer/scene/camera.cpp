#include "renderer/scene/camera.h"

#include "renderer/math/sampling.h"

namespace pathfarm {

Camera::Camera(const CameraDesc& desc, int width, int height)
    : desc_(desc),
      animated_(desc.transform.isAnimated()),
      staticCameraToWorld_(desc.transform.transformAt(0)),
      tanHalfFov_(std::tan(0.5f * desc.fovDegrees * kPi / 180.0f)),
      aspect_(static_cast<float>(width) / static_cast<float>(height)),
      shiftX_(desc.centreX * tanHalfFov_ * aspect_),
      shiftY_(desc.centreY * tanHalfFov_),
      width_(width),
      height_(height) {}

CameraDesc zoomedIn(CameraDesc desc, double factor, double centreX, double centreY) {
  const double halfFov = 0.5 * double{desc.fovDegrees} * kPi / 180.0;
  desc.fovDegrees = static_cast<float>(2.0 * std::atan(std::tan(halfFov) / factor) * 180.0 / kPi);
  // In units of the window's half width and height, the picture's are `factor`.
  desc.centreX = static_cast<float>((2.0 * centreX - 1.0) * factor);
  desc.centreY = static_cast<float>((1.0 - 2.0 * centreY) * factor);
  return desc;
}

Transform Camera::cameraToWorld(double seconds) const {
  return animated_ ? desc_.transform.transformAt(seconds) : staticCameraToWorld_;
}

Ray Camera::generateRay(Vec2f film, Vec2f lens, double seconds) const {
  return generateRay(film, lens, cameraToWorld(seconds));
}

Ray Camera::generateRay(Vec2f film, Vec2f lens, const Transform& toWorld) const {
  // A shift of 0 adds 0: a camera on its axis makes the same bits as without the shift.
  const float sx = (2.0f * film.x / static_cast<float>(width_) - 1.0f) * tanHalfFov_ * aspect_ + shiftX_;
  const float sy = (1.0f - 2.0f * film.y / static_cast<float>(height_)) * tanHalfFov_ + shiftY_;
  Vec3f origin{0, 0, 0};
  Vec3f direction{sx, sy, -1.0f};
  if (desc_.apertureRadius > 0) {
    // Thin lens: every ray through the lens meets the pinhole ray on the focal plane.
    const Vec3f focus = direction * desc_.focusDistance;
    const Vec2f disk = sampleUniformDisk(lens);
    origin = {disk.x * desc_.apertureRadius, disk.y * desc_.apertureRadius, 0};
    direction = focus - origin;
  }
  return {toWorld.point(origin), normalize(toWorld.vector(direction))};
}

}  // namespace pathfarm

namespace pathfarm {

std::optional<Vec2f> Camera::toFilm(Vec3f v) const {
  if (v.z >= 0) return std::nullopt;  // the camera looks along -z
  const float sx = v.x / -v.z, sy = v.y / -v.z;
  return Vec2f{(sx / (tanHalfFov_ * aspect_) - desc_.centreX + 1.0f) * 0.5f * static_cast<float>(width_),
               (1.0f - (sy / tanHalfFov_ - desc_.centreY)) * 0.5f * static_cast<float>(height_)};
}

std::optional<Vec2f> Camera::project(Vec3f point, double seconds) const {
  return project(point, cameraToWorld(seconds));
}

std::optional<Vec2f> Camera::project(Vec3f point, const Transform& toWorld) const {
  return toFilm(toWorld.inversePoint(point));
}

std::optional<Vec2f> Camera::projectDirection(Vec3f direction, double seconds) const {
  return projectDirection(direction, cameraToWorld(seconds));
}

std::optional<Vec2f> Camera::projectDirection(Vec3f direction, const Transform& toWorld) const {
  return toFilm(toWorld.inverseVector(direction));
}

}  // namespace pathfarm
