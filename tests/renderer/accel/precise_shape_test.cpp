// The double-precision shapes the specular manifold walk differentiates through: their
// placement agrees with the animation, and their analytic derivatives (time, tangents,
// normals) agree with central finite differences; the mesh BVH finds what testing every
// triangle finds.
#include <gtest/gtest.h>

#include "renderer/accel/precise_shape.h"
#include "test_support.h"

namespace pathfarm {
namespace {

void expectNearD(Vec3d a, Vec3d b, double tolerance, const char* what) {
  EXPECT_NEAR(a.x, b.x, tolerance) << what;
  EXPECT_NEAR(a.y, b.y, tolerance) << what;
  EXPECT_NEAR(a.z, b.z, tolerance) << what;
}

// Two keyed segments of translation, rotation about a tilted axis and scale.
AnimatedTrs tumbling(bool uniformScale) {
  AnimatedTrs a;
  a.setTranslationKeys({{0.0, {0, 0, 0}}, {1.0, {1, 0.5f, -0.25f}}, {2.0, {1.5f, 0, 0.5f}}});
  a.setRotationKeys({{0.0, Quaternion::fromAxisAngle({0.3f, 1, 0.2f}, 0.2f)},
                     {2.0, Quaternion::fromAxisAngle({0.3f, 1, 0.2f}, 1.4f)}});
  a.setScaleKeys({{0.0, {1, 1, 1}}, {2.0, uniformScale ? Vec3f{2, 2, 2} : Vec3f{2, 1, 1.5f}}});
  return a;
}

TEST(PreciseShape, MotionAgreesWithTheAnimationAndItsRateWithFiniteDifferences) {
  const AnimatedTrs animation = tumbling(false);
  const Vec3d p{0.3, -0.7, 0.4};
  for (const double t : {0.25, 0.5, 1.3, 1.9}) {
    const AffineMotion m = animation.motionAt(t);
    expectNearD(m.point(p), Vec3d(animation.transformAt(t).point(p.toFloat())), 1e-5, "placement");
    const double h = 1e-5;
    const Vec3d difference = (animation.motionAt(t + h).point(p) - animation.motionAt(t - h).point(p)) / (2 * h);
    expectNearD(m.velocity(p), difference, 1e-6, "velocity");
  }
  expectNearD(animation.motionAt(5.0).velocity(p), {}, 0, "after the last keys");
}

SceneObject sphereObject(const AnimatedTrs& transform) {
  SceneObject o;
  o.type = ShapeType::Sphere;
  o.radius = 0.7f;
  o.transform = transform;
  return o;
}

// A bumpy grid of triangles with interpolated normals.
std::shared_ptr<const TriangleMesh> bumpyGrid(int n) {
  auto mesh = std::make_shared<TriangleMesh>();
  const auto height = [](double x, double y) { return 0.1 * std::sin(3 * x) * std::cos(2 * y); };
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const double x = -1 + 2.0 * i / n, y = -1 + 2.0 * j / n;
      mesh->positions.push_back(Vec3d{x, y, height(x, y)}.toFloat());
      mesh->normals.push_back(
          normalize(Vec3d{-0.3 * std::cos(3 * x) * std::cos(2 * y), 0.2 * std::sin(3 * x) * std::sin(2 * y), 1})
              .toFloat());
    }
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const auto v = static_cast<uint32_t>(j * (n + 1) + i), w = static_cast<uint32_t>(n + 1);
      for (uint32_t k : {v, v + 1, v + w + 1, v, v + w + 1, v + w}) mesh->indices.push_back(k);
    }
  }
  return mesh;
}

// Finite differences of a hit's normal and position along its tangents and in time,
// against the analytic differentials, for a ray from `origin` towards `target`.
void expectDifferentialsMatch(const PreciseShape& shape, const SceneObject& object, Vec3d origin, Vec3d target,
                              double seconds) {
  const auto hitToward = [&](Vec3d point, double t) {
    return shape.intersect(origin, normalize(point - origin), 0, t);
  };
  const auto hit = hitToward(target, seconds);
  ASSERT_TRUE(hit.has_value());
  const double h = 1e-5;
  for (const auto& [tangent, dn] : {std::pair{hit->dpdu, hit->dndu}, std::pair{hit->dpdv, hit->dndv}}) {
    const auto plus = hitToward(hit->position + tangent * h, seconds),
               minus = hitToward(hit->position - tangent * h, seconds);
    ASSERT_TRUE(plus && minus);
    expectNearD((plus->position - minus->position) / (2 * h), tangent, 1e-4, "tangent");
    expectNearD((plus->normal - minus->normal) / (2 * h), dn, 1e-4, "normal derivative");
  }
  // In time: the same object-space point, its normal by the inverse transpose.
  const auto placedNormal = [&](double t) {
    const AffineMotion m = object.transform.motionAt(t);
    const Vec3d local = object.type == ShapeType::Sphere ? normalize(hit->shapePosition) : Vec3d();
    return normalize(m.linear.inverse().transposed() * local);
  };
  const AffineMotion later = object.transform.motionAt(seconds + h), earlier = object.transform.motionAt(seconds - h);
  expectNearD((later.point(hit->shapePosition) - earlier.point(hit->shapePosition)) / (2 * h), hit->velocity, 1e-6,
              "velocity");
  if (object.type == ShapeType::Sphere)
    expectNearD((placedNormal(seconds + h) - placedNormal(seconds - h)) / (2 * h), hit->dndt, 1e-6, "normal rate");
}

TEST(PreciseShape, SphereDifferentialsMatchFiniteDifferences) {
  const SceneObject object = sphereObject(tumbling(true));
  const PreciseShape shape(object);
  for (const double t : {0.3, 1.6}) {
    const Vec3d center = object.transform.motionAt(t).translation;
    expectDifferentialsMatch(shape, object, {0, 0, 5}, center + Vec3d{0.3, 0.2, 0.5}, t);
    const auto hit = shape.intersect({0, 0, 5}, normalize(center - Vec3d{0, 0, 5}), 0, t);
    ASSERT_TRUE(hit.has_value());
    EXPECT_NEAR(length(hit->position - center), object.radius * (1 + t / 2), 1e-12);  // the scale goes 1 to 2
    expectNearD(hit->normal, normalize(hit->position - center), 1e-12, "normal");
  }
}

TEST(PreciseShape, MeshDifferentialsMatchFiniteDifferences) {
  SceneObject object;
  object.mesh = bumpyGrid(8);
  object.transform = tumbling(false);
  const PreciseShape shape(object);
  for (const double t : {0.3, 1.6}) {
    const AffineMotion m = object.transform.motionAt(t);
    expectDifferentialsMatch(shape, object, m.point({0.2, 0.1, 3}), m.point({0.21, 0.13, 0}), t);
  }
}

TEST(PreciseShape, BvhFindsWhatTestingEveryTriangleFinds) {
  SceneObject object;
  object.mesh = bumpyGrid(40);
  const PreciseShape shape(object);
  const TriangleMesh& mesh = *object.mesh;
  int hits = 0;
  for (int i = 0; i < 400; ++i) {
    const Vec3d o{2 * test_support::hashed(1, 0, i, 0) - 1, 2 * test_support::hashed(1, 1, i, 0) - 1, 2};
    const Vec3d d =
        normalize(Vec3d{test_support::hashed(1, 2, i, 0) - 0.5, test_support::hashed(1, 3, i, 0) - 0.5, -2});
    // Every triangle, by its plane and the signs of the edge functions.
    double nearest = 1e30;
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
      const Vec3d a(mesh.positions[mesh.indices[3 * t]]), b(mesh.positions[mesh.indices[3 * t + 1]]),
          c(mesh.positions[mesh.indices[3 * t + 2]]);
      const Vec3d n = cross(b - a, c - a);
      const double s = dot(a - o, n) / dot(d, n);
      const Vec3d p = o + d * s;
      if (s > 0 && s < nearest && dot(cross(b - a, p - a), n) >= 0 && dot(cross(c - b, p - b), n) >= 0 &&
          dot(cross(a - c, p - c), n) >= 0)
        nearest = s;
    }
    const auto hit = shape.intersect(o, d, 0, 0);
    ASSERT_EQ(hit.has_value(), nearest < 1e30) << "ray " << i;
    if (!hit) continue;
    ++hits;
    EXPECT_NEAR(length(hit->position - o), nearest, 1e-9) << "ray " << i;
  }
  EXPECT_GT(hits, 300);
}

}  // namespace
}  // namespace pathfarm
