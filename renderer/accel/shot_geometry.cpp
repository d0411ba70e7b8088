#include "renderer/accel/shot_geometry.h"

#include <algorithm>
#include <cstring>

namespace pathfarm {
namespace {

TriangleMesh transformMesh(TriangleMesh world, const Transform& toWorld) {
  for (Vec3f& p : world.positions) p = toWorld.point(p);
  for (Vec3f& n : world.normals) n = normalize(toWorld.normal(n));
  // A mirroring transform flips the winding; swap two indices so the geometric normal
  // still agrees with the vertex normals and the emitting side.
  const auto& m = toWorld.matrix();
  const float det = m[0] * (m[5] * m[10] - m[6] * m[9]) - m[1] * (m[4] * m[10] - m[6] * m[8]) +
                    m[2] * (m[4] * m[9] - m[5] * m[8]);
  for (Vec3f& t : world.tangents) t = toWorld.vector(t);
  if (det < 0) {
    for (size_t i = 0; i + 2 < world.indices.size(); i += 3) std::swap(world.indices[i + 1], world.indices[i + 2]);
    for (float& sign : world.tangentSigns) sign = -sign;
  }
  return world;
}

// Makes every triangle's winding agree with its vertex normals, where the mesh has them:
// the geometric normal then says which side is outside (and which side emits) without
// a per-hit check, for intersection and light sampling alike.
TriangleMesh orientWindingToNormals(TriangleMesh mesh) {
  if (mesh.normals.empty()) return mesh;
  for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
    const uint32_t a = mesh.indices[i], b = mesh.indices[i + 1], c = mesh.indices[i + 2];
    const Vec3f faceNormal = cross(mesh.positions[b] - mesh.positions[a], mesh.positions[c] - mesh.positions[a]);
    if (dot(faceNormal, mesh.normals[a] + mesh.normals[b] + mesh.normals[c]) < 0)
      std::swap(mesh.indices[i + 1], mesh.indices[i + 2]);
  }
  return mesh;
}

PreparedShape prepare(const SceneObject& object) {
  PreparedShape shape;
  shape.type = object.type;
  shape.animated = object.transform.isAnimated();
  // Animated objects keep their object space (identity here); Embree places them per frame.
  const Transform toWorld = shape.animated ? Transform() : object.transform.transformAt(0);
  if (object.type == ShapeType::Sphere) {
    shape.center = toWorld.point({0, 0, 0});
    shape.radius = object.radius * length(toWorld.vector({1, 0, 0}));
  } else {
    shape.mesh = std::make_shared<TriangleMesh>(
        transformMesh(orientWindingToNormals(*object.mesh), toWorld));
  }
  return shape;
}

RTCGeometry makeGeometry(RTCDevice device, const PreparedShape& shape) {
  if (shape.type == ShapeType::Sphere) {
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    auto* vertex = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), 1));
    vertex[0] = shape.center.x;
    vertex[1] = shape.center.y;
    vertex[2] = shape.center.z;
    vertex[3] = shape.radius;
    return geometry;
  }
  const TriangleMesh& mesh = *shape.mesh;
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* positions = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.positions.size()));
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    positions[3 * i] = mesh.positions[i].x;
    positions[3 * i + 1] = mesh.positions[i].y;
    positions[3 * i + 2] = mesh.positions[i].z;
  }
  auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), mesh.triangleCount()));
  std::memcpy(indices, mesh.indices.data(), mesh.indices.size() * sizeof(uint32_t));
  return geometry;
}

RTCScene newScene(RTCDevice device) {
  RTCScene scene = rtcNewScene(device);
  // Built once and traced millions of times: spend build time for trace speed.
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
  return scene;
}

}  // namespace

ShotGeometry::ShotGeometry(const Scene& scene, const EmbreeDevice& device)
    : scene_(scene), device_(device), objectScenes_(scene.objects.size(), nullptr) {
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    shapes_.push_back(prepare(scene.objects[i]));
    const PreparedShape& shape = shapes_.back();
    RTCGeometry geometry = makeGeometry(device.get(), shape);
    rtcCommitGeometry(geometry);
    if (shape.animated) {
      objectScenes_[i] = newScene(device.get());
      rtcAttachGeometry(objectScenes_[i], geometry);
      rtcCommitScene(objectScenes_[i]);
    } else {
      if (!staticScene_) staticScene_ = newScene(device.get());
      const unsigned id = rtcAttachGeometry(staticScene_, geometry);
      staticObjects_.resize(id + 1, -1);
      staticObjects_[id] = static_cast<int>(i);
    }
    rtcReleaseGeometry(geometry);
  }
  if (staticScene_) rtcCommitScene(staticScene_);
  device.check("building the shot's geometry");
}

ShotGeometry::~ShotGeometry() {
  if (staticScene_) rtcReleaseScene(staticScene_);
  for (RTCScene s : objectScenes_) {
    if (s) rtcReleaseScene(s);
  }
}

}  // namespace pathfarm
