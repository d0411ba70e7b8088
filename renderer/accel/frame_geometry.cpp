#include "renderer/accel/frame_geometry.h"

#include <embree3/rtcore_quaternion.h>

#include <limits>

#include "renderer/accel/normal_mapping.h"
#include "renderer/accel/shutter_poses.h"

namespace pathfarm {
namespace {

constexpr unsigned kInvalid = RTC_INVALID_GEOMETRY_ID;

RTCQuaternionDecomposition decomposition(const Trs& trs) {
  RTCQuaternionDecomposition qd;
  rtcInitQuaternionDecomposition(&qd);
  rtcQuaternionDecompositionSetScale(&qd, trs.scale.x, trs.scale.y, trs.scale.z);
  rtcQuaternionDecompositionSetQuaternion(&qd, trs.rotation.w, trs.rotation.x, trs.rotation.y,
                                          trs.rotation.z);
  rtcQuaternionDecompositionSetTranslation(&qd, trs.translation.x, trs.translation.y,
                                           trs.translation.z);
  return qd;
}

// Embree interpolates between uniformly spaced time steps; two are exact while the motion
// over the shutter is one keyframe segment, more approximate a shutter that spans keys.
unsigned timeStepsFor(const AnimatedTrs& animation, double open, double close) {
  if (close <= open) return 1;
  return animation.hasKeyInside(open, close) ? 17 : 2;
}

// Vertex i's attribute blended between the posed steps around a time, as Embree blends
// a deforming mesh's positions.
Vec3f blendedVertex(const std::vector<TriangleMesh>& poses, std::vector<Vec3f> TriangleMesh::*attribute, uint32_t i,
                    std::pair<size_t, float> at) {
  const Vec3f a = (poses[at.first].*attribute)[i];
  return poses.size() == 1 ? a : lerp(a, (poses[at.first + 1].*attribute)[i], at.second);
}

}  // namespace

Vec2f sphereUv(Vec3f n) {
  const float phi = std::atan2(n.y, n.x);
  return {(phi < 0 ? phi + 2 * kPi : phi) / (2 * kPi), std::acos(std::clamp(n.z, -1.0f, 1.0f)) * kInvPi};
}

FrameGeometry::FrameGeometry(const ShotGeometry& shot, int64_t frame)
    : shot_(shot), frame_(frame), timeSteps_(shot.scene().objects.size()), poses_(shot.scene().objects.size()) {
  const Scene& scene = shot.scene();
  if (!shot.placesObjects()) {
    top_ = shot.staticScene();  // nothing moves: trace the static BVH directly
    return;
  }
  RTCDevice device = shot.device().get();
  top_ = rtcNewScene(device);
  ownsTop_ = true;
  rtcSetSceneBuildQuality(top_, RTC_BUILD_QUALITY_LOW);  // instances only, rebuilt per frame
  auto attach = [&](RTCScene child, int object) {
    RTCGeometry instance = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(instance, child);
    if (object < 0 || shot.shape(object).deforming) {
      const float identity[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
      rtcSetGeometryTransform(instance, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, identity);
    } else if (shot.shape(object).instanced) {
      rtcSetGeometryTransform(instance, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, shot.shape(object).placement.matrix().data());
    } else {
      const AnimatedTrs& animation = scene.objects[static_cast<size_t>(object)].transform;
      const double open = scene.timeAt(frame, 0), close = scene.timeAt(frame, 1);
      const unsigned steps = timeStepsFor(animation, open, close);
      rtcSetGeometryTimeStepCount(instance, steps);
      auto& trs = timeSteps_[static_cast<size_t>(object)];
      for (unsigned s = 0; s < steps; ++s) {
        const double t = steps == 1 ? open : open + (close - open) * s / (steps - 1);
        trs.push_back(animation.at(t));
        const RTCQuaternionDecomposition qd = decomposition(trs.back());
        rtcSetGeometryTransformQuaternion(instance, s, &qd);
      }
    }
    rtcCommitGeometry(instance);
    const unsigned id = rtcAttachGeometry(top_, instance);
    rtcReleaseGeometry(instance);
    instanceObject_.resize(id + 1, -1);
    instanceObject_[id] = object;
  };
  if (shot.staticScene()) attach(shot.staticScene(), -1);
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const int object = static_cast<int>(i);
    if (shot.shape(object).deforming) {
      attach(buildDeformed(object, scene.timeAt(frame, 0), scene.timeAt(frame, 1)), object);
    } else if (RTCScene child = shot.objectScene(object)) {
      attach(child, object);
    }
  }
  rtcCommitScene(top_);
  shot.device().check("placing the animated and instanced objects of a frame");
}

FrameGeometry::~FrameGeometry() {
  if (ownsTop_) rtcReleaseScene(top_);
  for (RTCScene s : deformedScenes_) rtcReleaseScene(s);
}

RTCScene FrameGeometry::buildDeformed(int object, double open, double close) {
  const PreparedShape& shape = shot_.shape(object);
  const MeshDeformation& deformation = *shot_.scene().objects[static_cast<size_t>(object)].deformation;
  auto& poses = poses_[static_cast<size_t>(object)];
  std::vector<const std::vector<Vec3f>*> positions;
  for (MeshDeformation::Pose& pose : shutterPoses(deformation, open, close)) {
    // What shading reads per vertex; the triangles stay the rest mesh's (wound to its normals).
    TriangleMesh posed;
    posed.uvs = shape.mesh->uvs;
    posed.tangentSigns = shape.mesh->tangentSigns;
    posed.positions = std::move(pose.positions);
    posed.normals = std::move(pose.normals);
    posed.tangents = std::move(pose.tangents);
    poses.push_back(std::move(posed));
  }
  for (const TriangleMesh& posed : poses) positions.push_back(&posed.positions);
  RTCDevice device = shot_.device().get();
  RTCGeometry geometry = newTriangleGeometry(device, shape, positions);
  rtcCommitGeometry(geometry);
  RTCScene scene = rtcNewScene(device);
  rtcAttachGeometry(scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(scene);
  deformedScenes_.push_back(scene);
  return scene;
}

std::pair<size_t, float> FrameGeometry::stepAt(size_t stepCount, float time) const {
  if (stepCount < 2) return {0, 0.0f};
  const float position = std::clamp(time, 0.0f, 1.0f) * static_cast<float>(stepCount - 1);
  const size_t i = std::min(static_cast<size_t>(position), stepCount - 2);
  return {i, position - static_cast<float>(i)};
}

Transform FrameGeometry::shapeToWorld(int object, float time) const {
  const auto& steps = timeSteps_[static_cast<size_t>(object)];
  if (steps.empty()) return shot_.shape(object).placement;
  if (steps.size() == 1) return Transform::fromTrs(steps[0]);
  // Embree's quaternion motion blur: linear in translation and scale, slerp in rotation,
  // between the two time steps around `time`.
  const auto [i, f] = stepAt(steps.size(), time);
  const Trs& a = steps[i];
  const Trs& b = steps[i + 1];
  return Transform::fromTrs({lerp(a.translation, b.translation, f), slerp(a.rotation, b.rotation, f),
                             lerp(a.scale, b.scale, f)});
}

bool FrameGeometry::intersect(const Ray& ray, float time, SurfaceHit& hit) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  rh.ray.org_x = ray.origin.x;
  rh.ray.org_y = ray.origin.y;
  rh.ray.org_z = ray.origin.z;
  rh.ray.dir_x = ray.direction.x;
  rh.ray.dir_y = ray.direction.y;
  rh.ray.dir_z = ray.direction.z;
  rh.ray.tnear = 0;
  rh.ray.tfar = std::numeric_limits<float>::infinity();
  rh.ray.time = time;
  rh.ray.mask = 0xffffffffu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = kInvalid;
  rh.hit.instID[0] = kInvalid;
  rtcIntersect1(top_, &context, &rh);
  if (rh.hit.geomID == kInvalid) return false;
  const unsigned instance = rh.hit.instID[0];
  const int animated = instance == kInvalid ? -1 : instanceObject_[instance];
  const int object = animated >= 0 ? animated : shot_.staticObject(rh.hit.geomID);
  hit = makeHit(ray, rh.ray.tfar, object, rh.hit.primID, rh.hit.u, rh.hit.v, time);
  return true;
}

bool FrameGeometry::occluded(Vec3f origin, Vec3f direction, float maxDistance, float time) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray;
  ray.org_x = origin.x;
  ray.org_y = origin.y;
  ray.org_z = origin.z;
  ray.dir_x = direction.x;
  ray.dir_y = direction.y;
  ray.dir_z = direction.z;
  ray.tnear = 0;
  ray.tfar = maxDistance;
  ray.time = time;
  ray.mask = 0xffffffffu;
  ray.id = 0;
  ray.flags = 0;
  rtcOccluded1(top_, &context, &ray);
  return ray.tfar < 0;  // Embree sets tfar to -inf on a hit
}

SurfaceHit FrameGeometry::makeHit(const Ray& ray, float distance, int object, unsigned primitive,
                                  float u, float v, float time) const {
  const PreparedShape& shape = shot_.shape(object);
  const Transform toWorld = shapeToWorld(object, time);
  SurfaceHit hit;
  hit.distance = distance;
  hit.object = object;
  hit.primitive = primitive;
  if (shape.type == ShapeType::Sphere) {
    // Re-project onto the sphere: the analytic point is more precise than o + t d.
    const Vec3f local = toWorld.inversePoint(ray.origin + ray.direction * distance) - shape.center;
    const Vec3f n = normalize(local);
    hit.shapePosition = shape.center + n * shape.radius;
    hit.position = toWorld.point(hit.shapePosition);
    hit.geometricNormal = normalize(toWorld.normal(n));
    hit.shadingNormal = hit.geometricNormal;
    hit.uv = sphereUv(n);
    return hit;
  }
  hit = triangleSurface(object, primitive, {u, v}, toWorld, time);
  hit.distance = distance;
  return hit;
}

SurfaceHit FrameGeometry::deformedSurface(int object, uint32_t primitive, Vec2f barycentric, float time) const {
  return triangleSurface(object, primitive, barycentric, Transform(), time);
}

SurfaceHit FrameGeometry::triangleSurface(int object, uint32_t primitive, Vec2f barycentric,
                                         const Transform& toWorld, float time) const {
  const PreparedShape& shape = shot_.shape(object);
  const TriangleMesh& mesh = *shape.mesh;
  const uint32_t i0 = mesh.indices[3 * primitive], i1 = mesh.indices[3 * primitive + 1],
                 i2 = mesh.indices[3 * primitive + 2];
  const float u = barycentric.x, v = barycentric.y, w = 1 - u - v;
  // A deforming mesh blends its two posed steps around `time` per vertex, as Embree does;
  // normal mapping reads the nearer step's tangents.
  const auto& poses = poses_[static_cast<size_t>(object)];
  const auto at = stepAt(poses.size(), time);
  const TriangleMesh& posed = poses.empty() ? mesh : poses[at.first + (at.second > 0.5f ? 1 : 0)];
  const auto vertex = [&](std::vector<Vec3f> TriangleMesh::*attribute, uint32_t i) {
    return poses.empty() ? (mesh.*attribute)[i] : blendedVertex(poses, attribute, i, at);
  };
  SurfaceHit hit;
  hit.object = object;
  hit.primitive = primitive;
  hit.barycentric = barycentric;
  const Vec3f p0 = vertex(&TriangleMesh::positions, i0), p1 = vertex(&TriangleMesh::positions, i1),
              p2 = vertex(&TriangleMesh::positions, i2);
  hit.shapePosition = p0 * w + p1 * u + p2 * v;
  hit.position = toWorld.point(hit.shapePosition);
  hit.geometricNormal = normalize(toWorld.normal(cross(p1 - p0, p2 - p0)));
  hit.shadingNormal = hit.geometricNormal;
  if (!mesh.normals.empty()) {
    const Vec3f n = vertex(&TriangleMesh::normals, i0) * w + vertex(&TriangleMesh::normals, i1) * u +
                    vertex(&TriangleMesh::normals, i2) * v;
    if (dot(n, n) > 0) hit.shadingNormal = normalize(toWorld.normal(n));
  }
  if (!mesh.uvs.empty()) {
    const Vec2f a = mesh.uvs[i0], b = mesh.uvs[i1], c = mesh.uvs[i2];
    hit.uv = {a.x * w + b.x * u + c.x * v, a.y * w + b.y * u + c.y * v};
  } else {
    hit.uv = {u, v};
  }
  const Scene& scene = shot_.scene();
  hit.shadingNormal = normalMappedShadingNormal(scene, scene.objects[static_cast<size_t>(object)], posed,
                                                {i0, i1, i2, u, v}, toWorld, hit.shadingNormal, hit.uv);
  return hit;
}

float FrameGeometry::deformedAreaScale(int object, uint32_t primitive, float time) const {
  const TriangleMesh& rest = *shot_.shape(object).mesh;
  const auto& poses = poses_[static_cast<size_t>(object)];
  const auto at = stepAt(poses.size(), time);
  Vec3f posed[3], unposed[3];
  for (size_t k = 0; k < 3; ++k) {
    const uint32_t i = rest.indices[3 * primitive + k];
    posed[k] = blendedVertex(poses, &TriangleMesh::positions, i, at);
    unposed[k] = rest.positions[i];
  }
  const auto area = [](const Vec3f* p) { return length(cross(p[1] - p[0], p[2] - p[0])); };
  return area(posed) / area(unposed);
}

Bounds3 FrameGeometry::bounds() const {
  RTCBounds b;
  rtcGetSceneBounds(top_, &b);
  return {{b.lower_x, b.lower_y, b.lower_z}, {b.upper_x, b.upper_y, b.upper_z}};
}

bool FrameGeometry::connects(const SurfaceHit& from, Vec3f target, float time) const {
  // Aim from the offset origin, and stop short of the target's own surface.
  const Vec3f origin = offsetRayOrigin(from, target - from.position);
  const Vec3f toTarget = target - origin;
  const float distance = length(toTarget);
  const float reach = distance - surfaceEpsilon(target);
  return reach <= 0 || !occluded(origin, toTarget / distance, reach, time);
}

bool FrameGeometry::escapes(const SurfaceHit& from, Vec3f direction, float time) const {
  return !occluded(offsetRayOrigin(from, direction), direction, std::numeric_limits<float>::infinity(), time);
}

float surfaceEpsilon(Vec3f p) {
  return 1e-4f * (1 + std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}));
}

Vec3f offsetRayOrigin(const SurfaceHit& hit, Vec3f direction) {
  const float epsilon = surfaceEpsilon(hit.position);
  return hit.position + hit.geometricNormal * (dot(direction, hit.geometricNormal) > 0 ? epsilon : -epsilon);
}

}  // namespace pathfarm
