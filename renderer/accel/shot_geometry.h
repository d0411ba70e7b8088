#pragma once
// The geometry of a shot, built once: one Embree BVH holding every static object in
// world space, and one BVH per animated object in its own object space. Frames only
// place the animated objects (FrameGeometry); nothing here is rebuilt per frame.
#include <memory>
#include <vector>

#include "renderer/accel/embree_device.h"
#include "renderer/scene/scene.h"

namespace pathfarm {

// An object's shape in the space its BVH was built in: world space for static objects,
// object space for animated ones.
struct PreparedShape {
  ShapeType type = ShapeType::Mesh;
  Vec3f center;    // spheres
  float radius = 0;  // spheres
  std::shared_ptr<const TriangleMesh> mesh;  // triangles
  bool animated = false;
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
  // The object-space BVH of an animated object (null for static objects).
  RTCScene objectScene(int object) const { return objectScenes_[static_cast<size_t>(object)]; }

 private:
  const Scene& scene_;
  const EmbreeDevice& device_;
  std::vector<PreparedShape> shapes_;
  RTCScene staticScene_ = nullptr;
  std::vector<int> staticObjects_;
  std::vector<RTCScene> objectScenes_;
};

}  // namespace pathfarm
