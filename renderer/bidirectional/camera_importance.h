#pragma once
// The camera as a sensor for bidirectional path tracing (Veach 1997, section 10.3): its
// importance We, the density of the directions it samples, and connections from scene
// points to the lens, for a pinhole or a thin lens.
//
// Conventions. The lens point is sampled uniformly over the aperture (area density
// 1 / (pi r^2)); a pinhole has a single point, whose density counts as 1 (a Dirac delta
// that cancels in every ratio). Given the lens point, directions are sampled uniformly
// over the film, which is the plane at distance 1 in front of the pinhole with area A:
// the solid-angle density is 1 / (A cos^3 theta). The importance is that of the whole
// film, We = 1 / (A lensArea cos^4 theta): it integrates to 1 over lens area and film
// solid angle (with the cosine), and a camera ray has We cos / (its density) = 1, as the
// path tracer assumes. A pixel's value is W H times the integral of f(X) over the paths
// that land in it (the pixel's importance is W H We, restricted to the pixel).
#include <optional>

#include "renderer/scene/camera.h"

namespace pathfarm {

// A scene point seen from a sampled lens point: what light tracing (t = 1) splats.
struct CameraConnection {
  Vec3f lensPoint;     // world space
  Vec3f direction;     // unit, from the lens point towards the scene point
  float distance = 0;
  Vec2f raster;        // continuous pixel position the path lands on
  float importance = 0;  // We of the ray (lensPoint, direction)
  float cosCamera = 0;   // between the direction and the viewing axis
};

class CameraImportance {
 public:
  CameraImportance(const CameraDesc& desc, int width, int height);

  int width() const { return width_; }
  int height() const { return height_; }
  const Camera& camera() const { return camera_; }
  bool isPinhole() const { return apertureRadius_ == 0; }
  // Area density of the lens point (1 for a pinhole, see above).
  float lensDensity() const { return 1 / lensArea_; }
  // The unit viewing axis at `seconds`: the camera vertex's "normal".
  Vec3f viewDirection(double seconds) const;

  // Where the ray from `lensPoint` along unit `direction` lands on the film; nothing if
  // it misses the film.
  std::optional<Vec2f> raster(Vec3f lensPoint, Vec3f direction, double seconds) const;
  // We of that ray, 0 when it misses the film.
  float importance(Vec3f lensPoint, Vec3f direction, double seconds) const;
  // Solid-angle density with which a camera ray from `lensPoint` takes `direction`
  // (over the whole film), 0 when it misses the film.
  float directionPdf(Vec3f lensPoint, Vec3f direction, double seconds) const;
  // Samples a lens point with `uLens` and connects it to `point`; nothing when the point
  // is not imaged on the film.
  std::optional<CameraConnection> connect(Vec3f point, double seconds, Vec2f uLens) const;

 private:
  float cosToAxis(Vec3f direction, double seconds) const;

  Camera camera_;
  float apertureRadius_, focusDistance_;
  float filmArea_;  // A: the film's area at distance 1
  float lensArea_;  // pi r^2, or 1 for a pinhole
  int width_, height_;
};

}  // namespace pathfarm
