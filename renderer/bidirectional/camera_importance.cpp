#include "renderer/bidirectional/camera_importance.h"

#include "renderer/math/sampling.h"

namespace pathfarm {

CameraImportance::CameraImportance(const CameraDesc& desc, int width, int height)
    : camera_(desc, width, height),
      apertureRadius_(desc.apertureRadius),
      focusDistance_(desc.focusDistance),
      width_(width),
      height_(height) {
  const float tanHalfFov = std::tan(0.5f * desc.fovDegrees * kPi / 180.0f);
  const float aspect = static_cast<float>(width) / static_cast<float>(height);
  filmArea_ = 4 * tanHalfFov * tanHalfFov * aspect;
  lensArea_ = apertureRadius_ > 0 ? kPi * apertureRadius_ * apertureRadius_ : 1.0f;
}

Vec3f CameraImportance::viewDirection(double seconds) const {
  return normalize(camera_.cameraToWorld(seconds).vector({0, 0, -1}));
}

float CameraImportance::cosToAxis(Vec3f direction, double seconds) const {
  return dot(direction, viewDirection(seconds));
}

std::optional<Vec2f> CameraImportance::raster(Vec3f lensPoint, Vec3f direction, double seconds) const {
  std::optional<Vec2f> film;
  if (isPinhole()) {
    film = camera_.projectDirection(direction, seconds);
  } else {
    // A thin lens images every ray through the point where it crosses the focal plane.
    const float cosTheta = cosToAxis(direction, seconds);
    if (cosTheta <= 0) return std::nullopt;
    film = camera_.project(lensPoint + direction * (focusDistance_ / cosTheta), seconds);
  }
  if (!film || !(film->x >= 0 && film->x < static_cast<float>(width_) && film->y >= 0 &&
                 film->y < static_cast<float>(height_)))
    return std::nullopt;
  return film;
}

float CameraImportance::importance(Vec3f lensPoint, Vec3f direction, double seconds) const {
  const float cosTheta = cosToAxis(direction, seconds);
  if (cosTheta <= 0 || !raster(lensPoint, direction, seconds)) return 0;
  const float cos2 = cosTheta * cosTheta;
  return 1 / (filmArea_ * lensArea_ * cos2 * cos2);
}

float CameraImportance::directionPdf(Vec3f lensPoint, Vec3f direction, double seconds) const {
  const float cosTheta = cosToAxis(direction, seconds);
  if (cosTheta <= 0 || !raster(lensPoint, direction, seconds)) return 0;
  return 1 / (filmArea_ * cosTheta * cosTheta * cosTheta);
}

std::optional<CameraConnection> CameraImportance::connect(Vec3f point, double seconds, Vec2f uLens) const {
  const Vec2f disk = isPinhole() ? Vec2f{0, 0} : sampleUniformDisk(uLens);
  CameraConnection c;
  c.lensPoint = camera_.cameraToWorld(seconds).point({disk.x * apertureRadius_, disk.y * apertureRadius_, 0});
  const Vec3f toPoint = point - c.lensPoint;
  c.distance = length(toPoint);
  if (!(c.distance > 0)) return std::nullopt;
  c.direction = toPoint / c.distance;
  c.cosCamera = cosToAxis(c.direction, seconds);
  const std::optional<Vec2f> film = raster(c.lensPoint, c.direction, seconds);
  if (c.cosCamera <= 0 || !film) return std::nullopt;
  c.raster = *film;
  c.importance = importance(c.lensPoint, c.direction, seconds);
  return c;
}

}  // namespace pathfarm
