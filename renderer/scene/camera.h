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
  // Where the picture's centre lies on the image plane, in units of its half width (x,
  // right) and half height (y, up): (0, 0) on the axis; elsewhere for a window of a
  // larger picture (zoomedIn).
  float centreX = 0, centreY = 0;
};

// The same camera seeing only 1/factor of its picture (per axis): its field of view
// narrowed so that a frame 1/factor the size, in pixels, has pixels of the same size. The
// window is centred on the picture's point (centreX, centreY), given as fractions of its
// width and height from the top left corner; by default the picture's centre.
CameraDesc zoomedIn(CameraDesc desc, double factor, double centreX = 0.5, double centreY = 0.5);

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
  float shiftX_, shiftY_;  // the picture's centre on the plane at distance 1
  int width_, height_;
};

}  // namespace pathfarm
