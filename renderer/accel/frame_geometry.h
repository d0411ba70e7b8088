#pragma once
// The scene during one frame's shutter interval: a small top-level Embree scene that
// instances the shot's static BVH and places every animated object's BVH with its
// motion over the shutter (Embree's quaternion motion blur). Ray times are fractions
// of the shutter interval, in [0, 1].
#include <vector>

#include "renderer/accel/shot_geometry.h"
#include "renderer/accel/surface_hit.h"
#include "renderer/scene/camera.h"

namespace pathfarm {

struct Bounds3 {
  Vec3f lower, upper;
};

class FrameGeometry {
 public:
  FrameGeometry(const ShotGeometry& shot, int64_t frame);
  ~FrameGeometry();
  FrameGeometry(const FrameGeometry&) = delete;
  FrameGeometry& operator=(const FrameGeometry&) = delete;

  bool intersect(const Ray& ray, float time, SurfaceHit& hit) const;
  // Whether anything lies along origin + s * direction for s in (0, maxDistance).
  bool occluded(Vec3f origin, Vec3f direction, float maxDistance, float time) const;
  // Shadow rays leaving a surface: whether `target` (a point on another surface) is in
  // sight, and whether a ray in `direction` leaves the scene.
  bool connects(const SurfaceHit& from, Vec3f target, float time) const;
  bool escapes(const SurfaceHit& from, Vec3f direction, float time) const;
  // The transform from the object's prepared shape to world space at `time`: Embree's
  // own interpolation for animated objects, identity for static ones (already in world)
  // and for deforming ones (posed in world space).
  Transform shapeToWorld(int object, float time) const;
  // The point at `barycentric` in triangle `primitive` of a deforming object at `time`,
  // as a hit would find it (position, normals, uv).
  SurfaceHit deformedSurface(int object, uint32_t primitive, Vec2f barycentric, float time) const;
  // The world area of that triangle at `time` over its rest area.
  float deformedAreaScale(int object, uint32_t primitive, float time) const;

  int64_t frame() const { return frame_; }
  const ShotGeometry& shot() const { return shot_; }
  Bounds3 bounds() const;
  RTCScene embreeScene() const { return top_; }

 private:
  SurfaceHit makeHit(const Ray& ray, float distance, int object, unsigned primitive, float u,
                     float v, float time) const;
  // Triangle `primitive` at `barycentric`: a rigid mesh's placed by `toWorld`, a
  // deforming mesh's posed at `time`.
  SurfaceHit triangleSurface(int object, uint32_t primitive, Vec2f barycentric, const Transform& toWorld,
                                    float time) const;
  // Poses a deforming object at the frame's time steps and builds its BVH.
  RTCScene buildDeformed(int object, double open, double close);
  // The step before `time` and the fraction of the way to the next, as Embree blends them.
  std::pair<size_t, float> stepAt(size_t stepCount, float time) const;

  const ShotGeometry& shot_;
  int64_t frame_;
  RTCScene top_ = nullptr;
  bool ownsTop_ = false;
  std::vector<int> instanceObject_;        // instance id -> animated object, -1 for the static BVH
  // Per object, its transform at the instance's uniformly spaced time steps (empty for
  // static objects), interpolated the way Embree does for shading.
  std::vector<std::vector<Trs>> timeSteps_;
  // Per deforming object, its poses at the shutter's instants (shutter_poses.h; empty for
  // the others), holding what shading reads per vertex, and the BVHs built from them.
  std::vector<std::vector<TriangleMesh>> poses_;
  std::vector<RTCScene> deformedScenes_;
};

// The surface coordinates of a sphere's point with object-space unit normal n.
Vec2f sphereUv(Vec3f n);
// Moves a ray's origin off the surface it leaves, to the side `direction` points to,
// so it cannot hit that surface again through rounding.
Vec3f offsetRayOrigin(const SurfaceHit& hit, Vec3f direction);
// How far from a point rounding errors can reach, scaled to its coordinates.
float surfaceEpsilon(Vec3f p);

}  // namespace pathfarm
