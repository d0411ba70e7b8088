#include "renderer/accel/shot_geometry.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <map>

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

uint32_t bitsOf(float f) {
  uint32_t bits;
  std::memcpy(&bits, &f, sizeof bits);
  return bits;
}

// Embree's filter for cut-out triangles: a hit where the surface is not there (MASK
// below the cutoff, or BLEND's pass-through) is rejected and the ray goes on. BLEND's
// random number hashes the hit and the ray's direction, so it is the same for the same
// ray everywhere.
void coverageFilter(const RTCFilterFunctionNArguments* args) {
  const auto& shape = *static_cast<const PreparedShape*>(args->geometryUserPtr);
  const TriangleMesh& mesh = *shape.mesh;
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const unsigned primitive = RTCHitN_primID(args->hit, args->N, i);
    const float u = RTCHitN_u(args->hit, args->N, i), v = RTCHitN_v(args->hit, args->N, i);
    Vec2f uv{u, v};
    if (!mesh.uvs.empty()) {
      const Vec2f a = mesh.uvs[mesh.indices[3 * primitive]], b = mesh.uvs[mesh.indices[3 * primitive + 1]],
                  c = mesh.uvs[mesh.indices[3 * primitive + 2]];
      const float w = 1 - u - v;
      uv = {a.x * w + b.x * u + c.x * v, a.y * w + b.y * u + c.y * v};
    }
    const float random = hashToUnit(primitive, bitsOf(u), bitsOf(v),
                                    bitsOf(RTCRayN_dir_x(args->ray, args->N, i)) ^
                                        bitsOf(RTCRayN_dir_y(args->ray, args->N, i)) * 3u ^
                                        bitsOf(RTCRayN_dir_z(args->ray, args->N, i)) * 7u);
    if (!shape.coverage->covers(uv, random)) args->valid[i] = 0;
  }
}

// Static meshes with the same mesh and cut-out share one BVH when placed more than once.
using SharingKey = std::pair<const TriangleMesh*, int>;
SharingKey sharingKey(const Scene& scene, const SceneObject& object) {
  return {object.mesh.get(), scene.materials[static_cast<size_t>(object.material)].coverage};
}

PreparedShape prepare(const Scene& scene, const SceneObject& object, bool instanced) {
  PreparedShape shape;
  const int coverage = scene.materials[static_cast<size_t>(object.material)].coverage;
  if (coverage >= 0 && object.type != ShapeType::Sphere) shape.coverage = &scene.coverages[static_cast<size_t>(coverage)];
  shape.type = object.type;
  shape.animated = object.transform.isAnimated();
  shape.deforming = object.deformation != nullptr;
  shape.instanced = instanced;
  if (instanced) shape.placement = object.transform.transformAt(0);
  // Animated and instanced objects keep their object space (identity here); Embree places
  // them per frame.
  const Transform toWorld = shape.animated || instanced ? Transform() : object.transform.transformAt(0);
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
  return newTriangleGeometry(device, shape, {&shape.mesh->positions});
}

RTCScene newScene(RTCDevice device) {
  RTCScene scene = rtcNewScene(device);
  // Built once and traced millions of times: spend build time for trace speed.
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
  return scene;
}

// The world-space box around `local` placed by `toWorld`.
RTCBounds placedBounds(const RTCBounds& local, const Transform& toWorld) {
  RTCBounds world{};
  world.lower_x = world.lower_y = world.lower_z = std::numeric_limits<float>::infinity();
  world.upper_x = world.upper_y = world.upper_z = -std::numeric_limits<float>::infinity();
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3f p = toWorld.point({corner & 1 ? local.upper_x : local.lower_x, corner & 2 ? local.upper_y : local.lower_y,
                                   corner & 4 ? local.upper_z : local.lower_z});
    world.lower_x = std::min(world.lower_x, p.x), world.upper_x = std::max(world.upper_x, p.x);
    world.lower_y = std::min(world.lower_y, p.y), world.upper_y = std::max(world.upper_y, p.y);
    world.lower_z = std::min(world.lower_z, p.z), world.upper_z = std::max(world.upper_z, p.z);
  }
  return world;
}

void extend(RTCBounds& bounds, const RTCBounds& by) {
  bounds.lower_x = std::min(bounds.lower_x, by.lower_x), bounds.upper_x = std::max(bounds.upper_x, by.upper_x);
  bounds.lower_y = std::min(bounds.lower_y, by.lower_y), bounds.upper_y = std::max(bounds.upper_y, by.upper_y);
  bounds.lower_z = std::min(bounds.lower_z, by.lower_z), bounds.upper_z = std::max(bounds.upper_z, by.upper_z);
}

}  // namespace

RTCGeometry newTriangleGeometry(RTCDevice device, const PreparedShape& shape,
                                const std::vector<const std::vector<Vec3f>*>& positionsPerStep) {
  const TriangleMesh& mesh = *shape.mesh;
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetGeometryTimeStepCount(geometry, static_cast<unsigned>(positionsPerStep.size()));
  for (size_t step = 0; step < positionsPerStep.size(); ++step) {
    const std::vector<Vec3f>& points = *positionsPerStep[step];
    auto* positions = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX,
                                                                  static_cast<unsigned>(step), RTC_FORMAT_FLOAT3,
                                                                  3 * sizeof(float), points.size()));
    for (size_t i = 0; i < points.size(); ++i) {
      positions[3 * i] = points[i].x;
      positions[3 * i + 1] = points[i].y;
      positions[3 * i + 2] = points[i].z;
    }
  }
  auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), mesh.triangleCount()));
  std::memcpy(indices, mesh.indices.data(), mesh.indices.size() * sizeof(uint32_t));
  if (shape.coverage) {
    rtcSetGeometryUserData(geometry, const_cast<PreparedShape*>(&shape));
    rtcSetGeometryIntersectFilterFunction(geometry, coverageFilter);
    rtcSetGeometryOccludedFilterFunction(geometry, coverageFilter);
  }
  return geometry;
}

ShotGeometry::ShotGeometry(const Scene& scene, const EmbreeDevice& device)
    : scene_(scene), device_(device), objectScenes_(scene.objects.size(), nullptr) {
  // A mesh placed more than once, still or animated, gets one object-space BVH that every
  // placement instances.
  std::map<SharingKey, int> placements;
  for (const SceneObject& object : scene.objects)
    if (object.type != ShapeType::Sphere && !object.deformation) ++placements[sharingKey(scene, object)];
  std::map<SharingKey, size_t> firstPlacement;  // whose prepared mesh and BVH the others share

  shapes_.reserve(scene.objects.size());  // the coverage filters hold pointers to them
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const SceneObject& object = scene.objects[i];
    const bool shared =
        object.type != ShapeType::Sphere && !object.deformation && placements[sharingKey(scene, object)] > 1;
    const bool instanced = shared && !object.transform.isAnimated();
    if (shared) {
      const auto [first, isFirst] = firstPlacement.try_emplace(sharingKey(scene, object), i);
      if (!isFirst) {
        PreparedShape shape = shapes_[first->second];
        shape.animated = object.transform.isAnimated();
        shape.instanced = instanced;
        shape.placement = instanced ? object.transform.transformAt(0) : Transform();
        shapes_.push_back(std::move(shape));
        objectScenes_[i] = objectScenes_[first->second];
        placesObjects_ = true;
        continue;
      }
    }
    shapes_.push_back(prepare(scene, object, instanced));
    const PreparedShape& shape = shapes_.back();
    if (shape.deforming) {  // its BVH is built per frame
      placesObjects_ = true;
      continue;
    }
    RTCGeometry geometry = makeGeometry(device.get(), shape);
    rtcCommitGeometry(geometry);
    if (shape.animated || shape.instanced) {
      objectScenes_[i] = newScene(device.get());
      ownedScenes_.push_back(objectScenes_[i]);
      rtcAttachGeometry(objectScenes_[i], geometry);
      rtcCommitScene(objectScenes_[i]);
      placesObjects_ = true;
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

  staticBounds_.lower_x = staticBounds_.lower_y = staticBounds_.lower_z = std::numeric_limits<float>::infinity();
  staticBounds_.upper_x = staticBounds_.upper_y = staticBounds_.upper_z = -std::numeric_limits<float>::infinity();
  RTCBounds local;
  if (staticScene_) {
    rtcGetSceneBounds(staticScene_, &local);
    extend(staticBounds_, local);
  }
  for (size_t i = 0; i < shapes_.size(); ++i) {
    if (!shapes_[i].instanced) continue;
    rtcGetSceneBounds(objectScenes_[i], &local);
    extend(staticBounds_, placedBounds(local, shapes_[i].placement));
  }
}

Vec3f ShotGeometry::surfacePointAt(const SurfaceHit& hit, double seconds) const {
  const PreparedShape& shape = shapes_[static_cast<size_t>(hit.object)];
  const SceneObject& object = scene_.objects[static_cast<size_t>(hit.object)];
  if (shape.animated) return object.transform.transformAt(seconds).point(hit.shapePosition);
  if (!shape.deforming) return hit.position;
  const uint32_t* corners = &shape.mesh->indices[3 * hit.primitive];
  const float u = hit.barycentric.x, v = hit.barycentric.y;
  return object.deformation->positionAt(corners[0], seconds) * (1 - u - v) +
         object.deformation->positionAt(corners[1], seconds) * u + object.deformation->positionAt(corners[2], seconds) * v;
}

ShotGeometry::~ShotGeometry() {
  if (staticScene_) rtcReleaseScene(staticScene_);
  for (RTCScene s : ownedScenes_) rtcReleaseScene(s);
}

}  // namespace pathfarm
