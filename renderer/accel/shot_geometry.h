#pragma once
// The geometry of a shot, built once: one Embree BVH holding every static object in
// world space, and one object-space BVH per animated object or per mesh that several
// objects place (still or animated: the placements instance it, so memory does not grow
// with the number of copies). Frames only place the animated and instanced objects
// (FrameGeometry); nothing here is rebuilt per frame.
#include <memory>
#include <vector>

#include "renderer/accel/embree_device.h"
#include "renderer/accel/surface_hit.h"
#include "renderer/scene/scene.h"

namespace pathfarm {

// An object's shape in the space its BVH was built in: world space for static objects,
// object space for animated and instanced ones.
struct PreparedShape {
  ShapeType type = ShapeType::Mesh;
  Vec3f center;    // spheres
  float radius = 0;  // spheres
  std::shared_ptr<const TriangleMesh> mesh;  // triangles; one for all instances of a mesh
  bool animated = false;
  // Its vertices move on their own (SceneObject::deformation): FrameGeometry builds its
  // BVH per frame from the poses across the shutter. `mesh` keeps the rest pose.
  bool deforming = false;
  // Static, but placed by an Embree instance of its mesh's shared BVH.
  bool instanced = false;
  // To world space for objects that do not move: the placement of an instanced object,
  // identity for shapes built in world space.
  Transform placement;
  const AlphaCoverage* coverage = nullptr;  // cut-out triangles, tested by Embree's filter
};

class ShotGeometry {
 public:
  ShotGeometry(const Scene& scene, const EmbreeDevice& device);
  ~ShotGeometry();
  ShotGeometry(const ShotGeometry&) = delete;
  ShotGeometry& operator=(const ShotGeometry&) = delete;

  const Scene& scene() const { return scene_; }
  const EmbreeDevice& device() const { return device_; }
  const PreparedShape& shape(int object) const { return shapes_[static_cast<size_t>(object)]; }
  // The static objects' BVH (null if every object is animated) and the object each of
  // its geometries is.
  RTCScene staticScene() const { return staticScene_; }
  int staticObject(unsigned geomId) const { return staticObjects_[geomId]; }
  // The object-space BVH of an animated or instanced object (null for the others); the
  // placements of one mesh share theirs.
  RTCScene objectScene(int object) const { return objectScenes_[static_cast<size_t>(object)]; }
  // Where the surface point `hit` found is at `seconds`: carried by its object's
  // animation, or by a deforming mesh's vertices (the same triangle and barycentric
  // coordinates); a still object's stays where it is.
  Vec3f surfacePointAt(const SurfaceHit& hit, double seconds) const;
  // Whether some object must be placed per frame (animated, instanced or deforming).
  bool placesObjects() const { return placesObjects_; }
  // The world-space bounds of everything that does not move, instances included.
  const RTCBounds& staticBounds() const { return staticBounds_; }

 private:
  const Scene& scene_;
  const EmbreeDevice& device_;
  std::vector<PreparedShape> shapes_;
  RTCScene staticScene_ = nullptr;
  std::vector<int> staticObjects_;
  std::vector<RTCScene> objectScenes_;
  std::vector<RTCScene> ownedScenes_;  // every object-space BVH, once
  bool placesObjects_ = false;
  RTCBounds staticBounds_{};
};

// An Embree triangle geometry of `shape`'s mesh with one vertex buffer per time step
// (one for a still mesh), cut-outs filtered; the caller commits it.
RTCGeometry newTriangleGeometry(RTCDevice device, const PreparedShape& shape,
                                const std::vector<const std::vector<Vec3f>*>& positionsPerStep);

}  // namespace pathfarm
