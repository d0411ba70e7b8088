#pragma once
// A perspective camera with an optional thin lens, animated like any object. It looks
// along -z of its own frame with +y up; the vertical field of view is given.
#include <optional>

#include "renderer/math/animation.h"

namespace pathfarm {

struct Ray {
  Vec3f origin;
  Vec3f direction;  // unit length
};

struct CameraDesc {
  AnimatedTrs transform;   // camera to world; the rest rotation already holds the look-at
  float fovDegrees = 40;   // vertical
  float apertureRadius = 0;  // 0: a pinhole
  float focusDistance = 1;
  // The shutter, as fractions of a frame after the frame's start.
  float shutterOpen = 0;
  float shutterClose = 0;
};

// The same camera seeing only the centre 1/factor of its picture (per axis): its field of
// view narrowed so that a frame 1/factor the size, in pixels, has pixels of the same size.
CameraDesc zoomedIn(CameraDesc desc, double factor);

class Camera {
 public:
  Camera(const CameraDesc& desc, int width, int height);

  // `film` is a continuous pixel position (x right, y down, pixel (i,j) covers
  // [i,i+1)x[j,j+1)); `lens` a point in the unit square; `seconds` the ray's time.
  Ray generateRay(Vec2f film, Vec2f lens, double seconds) const;
  // The same, with cameraToWorld(seconds) given: rays sharing a time share its cost.
  Ray generateRay(Vec2f film, Vec2f lens, const Transform& toWorld) const;
  Transform cameraToWorld(double seconds) const;
  bool isAnimated() const { return animated_; }
  // Where a world point is imaged at `seconds` (the pinhole projection, the centre of a
  // thin lens's blur), as a continuous pixel position; nothing if it is behind the camera.
  std::optional<Vec2f> project(Vec3f point, double seconds) const;
  // The same, with cameraToWorld(seconds) given.
  std::optional<Vec2f> project(Vec3f point, const Transform& toWorld) const;
  // Where a direction (a point at infinity) is imaged.
  std::optional<Vec2f> projectDirection(Vec3f direction, double seconds) const;
  std::optional<Vec2f> projectDirection(Vec3f direction, const Transform& toWorld) const;

 private:
  const CameraDesc& desc_;
  bool animated_;
  Transform staticCameraToWorld_;
  std::optional<Vec2f> toFilm(Vec3f cameraSpace) const;
  float tanHalfFov_, aspect_;
  int width_, height_;
};

}  // namespace pathfarm
