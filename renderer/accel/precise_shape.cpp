#include "renderer/accel/precise_shape.h"

#include <limits>
#include <map>

namespace pathfarm {
namespace {

constexpr double kEdgeSlack = 1e-12;

}  // namespace

std::optional<PreciseShape::LocalHit> PreciseShape::intersectSphere(Vec3d o, Vec3d d, double minDistance) const {
  const double r = object_.radius;
  const double a = dot(d, d), b = dot(o, d), c = dot(o, o) - r * r;
  const double discriminant = b * b - a * c;
  if (!(discriminant >= 0) || a == 0) return std::nullopt;
  // The two roots without cancellation.
  const double q = -(b + std::copysign(std::sqrt(discriminant), b));
  double near = q / a, far = q != 0 ? c / q : near;
  if (near > far) std::swap(near, far);
  const double s = near > minDistance ? near : far;
  if (!(s > minDistance)) return std::nullopt;
  LocalHit hit;
  hit.normal = normalize(o + d * s);
  hit.position = hit.normal * r;  // back onto the sphere: more precise than o + s d
  const Tangents tangents = tangentsOf(hit.normal);
  hit.dpdu = tangents.s;
  hit.dpdv = tangents.t;
  hit.dndu = hit.dpdu / r;
  hit.dndv = hit.dpdv / r;
  return hit;
}

PreciseShape::PreciseShape(const SceneObject& object, std::shared_ptr<const TriangleBvh> bvh)
    : object_(object),
      animated_(object.transform.isAnimated()),
      still_(object.transform.motionAt(0)),
      bvh_(std::move(bvh)) {}

PreciseShape::PreciseShape(const SceneObject& object)
    : PreciseShape(object, object.type == ShapeType::Sphere ? nullptr : std::make_shared<const TriangleBvh>(*object.mesh)) {}

std::optional<PreciseShape::LocalHit> PreciseShape::intersectMesh(Vec3d o, Vec3d d, double minDistance) const {
  double nearest = std::numeric_limits<double>::infinity();
  std::optional<LocalHit> hit;
  bvh_->forEachCandidate(o, d, minDistance, nearest, [&](uint32_t triangle) {
    if (auto h = intersectTriangle(triangle, o, d, minDistance, nearest)) hit = h;
  });
  return hit;
}

std::optional<PreciseShape::LocalHit> PreciseShape::intersectTriangle(uint32_t triangle, Vec3d o, Vec3d d,
                                                                      double minDistance, double& nearest) const {
  const TriangleMesh& mesh = *object_.mesh;
  const uint32_t i0 = mesh.indices[3 * triangle], i1 = mesh.indices[3 * triangle + 1],
                 i2 = mesh.indices[3 * triangle + 2];
  const Vec3d p0(mesh.positions[i0]);
  const Vec3d e1 = Vec3d(mesh.positions[i1]) - p0, e2 = Vec3d(mesh.positions[i2]) - p0;
  const Vec3d faceNormal = cross(e1, e2);
  // Zero-area triangles have no plane to hit (and no tangents to differentiate).
  if (!(dot(faceNormal, faceNormal) > 1e-24 * dot(e1, e1) * dot(e2, e2))) return std::nullopt;
  // Moller-Trumbore. Barycentrics get a rounding's worth of slack, so that a ray along
  // the edge two triangles share hits one of them.
  const Vec3d p = cross(d, e2);
  const double det = dot(e1, p);
  if (det == 0) return std::nullopt;
  const Vec3d toOrigin = o - p0;
  const double u = dot(toOrigin, p) / det;
  if (!(u >= -kEdgeSlack && u <= 1 + kEdgeSlack)) return std::nullopt;
  const Vec3d q = cross(toOrigin, e1);
  const double v = dot(d, q) / det;
  if (!(v >= -kEdgeSlack && u + v <= 1 + kEdgeSlack)) return std::nullopt;
  const double s = dot(e2, q) / det;
  if (!(s > minDistance && s < nearest)) return std::nullopt;
  nearest = s;
  LocalHit h;
  h.position = p0 + e1 * u + e2 * v;
  h.dpdu = e1;
  h.dpdv = e2;
  h.primitive = triangle;
  h.normal = normalize(faceNormal);
  if (!mesh.normals.empty()) {
    const Vec3d n0(mesh.normals[i0]), n1(mesh.normals[i1]), n2(mesh.normals[i2]);
    const Vec3d interpolated = n0 * (1 - u - v) + n1 * u + n2 * v;
    const double l = length(interpolated);
    if (l > 0) {
      h.normal = interpolated / l;
      h.dndu = rejectFrom(n1 - n0, h.normal) / l;
      h.dndv = rejectFrom(n2 - n0, h.normal) / l;
    }
  }
  return h;
}

std::optional<SurfaceDifferentials> PreciseShape::intersect(Vec3d origin, Vec3d direction, double minDistance,
                                                            double seconds) const {
  if (deforms()) return std::nullopt;  // only its rest pose is held here (deforms())
  const AffineMotion placement = placementAt(seconds);
  const Mat3d toLocal = placement.linear.inverse();
  // The ray parameter is the same in both spaces: the local direction is not renormalized.
  const Vec3d o = toLocal * (origin - placement.translation), d = toLocal * direction;
  const std::optional<LocalHit> local =
      object_.type == ShapeType::Sphere ? intersectSphere(o, d, minDistance) : intersectMesh(o, d, minDistance);
  if (!local) return std::nullopt;
  SurfaceDifferentials s;
  s.shapePosition = local->position;
  s.primitive = local->primitive;
  s.position = placement.point(local->position);
  s.dpdu = placement.vector(local->dpdu);
  s.dpdv = placement.vector(local->dpdv);
  s.velocity = placement.velocity(local->position);
  // Normals go by the inverse transpose; the derivative of normalize(m) is the part of
  // dm orthogonal to the normal over |m|.
  const Mat3d normalMatrix = toLocal.transposed();
  const Vec3d m = normalMatrix * local->normal;
  const double ml = length(m);
  s.normal = m / ml;
  const auto turn = [&](Vec3d dm) { return rejectFrom(dm, s.normal) / ml; };
  s.dndu = turn(normalMatrix * local->dndu);
  s.dndv = turn(normalMatrix * local->dndv);
  // d(L^-T)/dt = -L^-T (dL/dt)^T L^-T.
  s.dndt = turn(-(normalMatrix * (placement.linearRate.transposed() * m)));
  return s;
}

std::vector<PreciseShape> preciseShapesOf(const Scene& scene) {
  std::vector<PreciseShape> shapes;
  shapes.reserve(scene.objects.size());
  std::map<const TriangleMesh*, std::shared_ptr<const TriangleBvh>> bvhOfMesh;
  for (const SceneObject& object : scene.objects) {
    std::shared_ptr<const TriangleBvh> bvh;
    if (object.type != ShapeType::Sphere && !object.deformation) {  // a deforming mesh is never traced here
      auto& shared = bvhOfMesh[object.mesh.get()];
      if (!shared) shared = std::make_shared<const TriangleBvh>(*object.mesh);
      bvh = shared;
    }
    shapes.emplace_back(object, std::move(bvh));
  }
  return shapes;
}

}  // namespace pathfarm
