#pragma once
// One scene object intersected in double precision at any time of its animation, with
// the local differential geometry of the hit: tangents, the shading normal and its
// derivatives (curvature), and the time derivatives of both at a fixed surface point.
// Spheres are exact; triangles interpolate their vertex normals, as shading does. The
// specular manifold walk differentiates through these (Jakob 2013, Section 4.3.1).
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "renderer/accel/triangle_bvh.h"
#include "renderer/math/affine_motion.h"
#include "renderer/scene/scene.h"

namespace pathfarm {

struct SurfaceDifferentials {
  Vec3d position;
  Vec3d dpdu, dpdv;     // tangents of the surface parametrization at the point
  Vec3d normal;         // unit shading normal, on the object's outward side
  Vec3d dndu, dndv;     // its derivatives along u and v
  Vec3d velocity;       // d(position)/dt at fixed (u, v): the object's motion
  Vec3d dndt;           // d(normal)/dt at fixed (u, v)
  Vec3d shapePosition;  // the point in object space
  uint32_t primitive = 0;
};

class PreciseShape {
 public:
  // `bvh` is the mesh's double-precision BVH (null for spheres and deforming meshes), shared by every object
  // that places the same mesh.
  PreciseShape(const SceneObject& object, std::shared_ptr<const TriangleBvh> bvh);
  // With a BVH of its own.
  explicit PreciseShape(const SceneObject& object);

  bool isAnimated() const { return animated_; }
  // A deforming mesh (SceneObject::deformation) is not held here: intersect() never hits
  // it, and the specular walk, which differentiates rigid motion, leaves its chains alone.
  bool deforms() const { return object_.deformation != nullptr; }
  AffineMotion placementAt(double seconds) const {
    return animated_ ? object_.transform.motionAt(seconds) : still_;
  }
  // The nearest hit along origin + s * direction with s > minDistance, at `seconds`.
  // Degenerate (zero-area) triangles are never hit.
  std::optional<SurfaceDifferentials> intersect(Vec3d origin, Vec3d direction, double minDistance,
                                                double seconds) const;

 private:
  struct LocalHit {
    Vec3d position, dpdu, dpdv, normal, dndu, dndv;
    uint32_t primitive = 0;
  };
  std::optional<LocalHit> intersectSphere(Vec3d origin, Vec3d direction, double minDistance) const;
  std::optional<LocalHit> intersectMesh(Vec3d origin, Vec3d direction, double minDistance) const;
  // The triangle's hit nearer than `nearest`, which it then lowers.
  std::optional<LocalHit> intersectTriangle(uint32_t triangle, Vec3d origin, Vec3d direction, double minDistance,
                                            double& nearest) const;

  const SceneObject& object_;
  bool animated_;
  AffineMotion still_;  // the placement of an object that does not move
  std::shared_ptr<const TriangleBvh> bvh_;  // meshes
};

// One per scene object, in the scene's order.
std::vector<PreciseShape> preciseShapesOf(const Scene& scene);

}  // namespace pathfarm
