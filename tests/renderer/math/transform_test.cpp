#include <gtest/gtest.h>

#include <random>

#include "renderer/math/frame.h"
#include "renderer/math/transform.h"
#include "test_support.h"

namespace pathfarm {
namespace {

using test_support::expectNear;

Trs randomTrs(std::mt19937& random) {
  std::uniform_real_distribution<float> u(-2, 2), positive(0.2f, 3);
  return {{u(random), u(random), u(random)},
          Quaternion::fromAxisAngle({u(random), u(random), u(random) + 0.1f}, u(random)),
          {positive(random), -positive(random), positive(random)}};
}

TEST(Transform, TrsInverseUndoesTheTransform) {
  std::mt19937 random(3);
  for (int i = 0; i < 100; ++i) {
    const Transform t = Transform::fromTrs(randomTrs(random));
    const Vec3f p{0.3f, -1.2f, 2.5f};
    expectNear(t.inversePoint(t.point(p)), p, 1e-4f);
    expectNear(t.inverseVector(t.vector(p)), p, 1e-4f);
    // The general inverse (fromMatrix) agrees with the analytic one.
    const Transform general = Transform::fromMatrix(t.matrix());
    expectNear(general.inversePoint(p), t.inversePoint(p), 1e-4f);
  }
}

TEST(Transform, NormalsStayPerpendicularUnderUnevenScale) {
  std::mt19937 random(4);
  for (int i = 0; i < 100; ++i) {
    const Transform t = Transform::fromTrs(randomTrs(random));
    const Vec3f n = normalize(Vec3f{1, 2, 3}), tangent = normalize(Vec3f{2, -1, 0});
    ASSERT_NEAR(dot(n, tangent), 0, 1e-6f);
    EXPECT_NEAR(dot(normalize(t.normal(n)), normalize(t.vector(tangent))), 0, 1e-5f);
  }
}

TEST(Transform, CompositionAppliesRightOperandFirst) {
  const Transform move = Transform::fromTrs({{1, 0, 0}, {}, {1, 1, 1}});
  const Transform grow = Transform::fromTrs({{0, 0, 0}, {}, {2, 2, 2}});
  expectNear((move * grow).point({1, 1, 1}), {3, 2, 2});
  expectNear((move * grow).inversePoint({3, 2, 2}), {1, 1, 1});
}

TEST(Transform, LookAtLooksDownMinusZ) {
  const Transform view = Transform::lookAt({1, 2, 3}, {1, 2, -7}, {0, 1, 0});
  expectNear(view.point({0, 0, 0}), {1, 2, 3});
  expectNear(view.vector({0, 0, -1}), {0, 0, -1});
  const Transform side = Transform::lookAt({0, 0, 0}, {5, 0, 0}, {0, 1, 0});
  expectNear(side.vector({0, 0, -1}), {1, 0, 0});
  expectNear(side.vector({0, 1, 0}), {0, 1, 0});
}

TEST(Quaternion, FromBasisRecoversTheRotation) {
  std::mt19937 random(5);
  std::uniform_real_distribution<float> u(-3, 3);
  for (int i = 0; i < 200; ++i) {
    const Quaternion q = Quaternion::fromAxisAngle({u(random), u(random), u(random) + 0.01f}, u(random));
    const Quaternion back = Quaternion::fromBasis(q.rotate({1, 0, 0}), q.rotate({0, 1, 0}), q.rotate({0, 0, 1}));
    const Vec3f v{0.2f, -0.7f, 1.1f};
    expectNear(back.rotate(v), q.rotate(v), 1e-4f);
  }
}

TEST(Frame, IsOrthonormalForAnyNormal) {
  std::mt19937 random(6);
  std::uniform_real_distribution<float> u(-1, 1);
  for (int i = 0; i < 1000; ++i) {
    const Vec3f n = normalize(Vec3f{u(random), u(random), u(random)});
    const Frame f = Frame::fromNormal(n);
    EXPECT_NEAR(length(f.s), 1, 1e-5f);
    EXPECT_NEAR(length(f.t), 1, 1e-5f);
    EXPECT_NEAR(dot(f.s, f.t), 0, 1e-5f);
    EXPECT_NEAR(dot(f.s, n), 0, 1e-5f);
    expectNear(cross(f.s, f.t), n, 1e-5f);  // right-handed
    const Vec3f v{0.3f, 0.4f, -0.5f};
    expectNear(f.toLocal(f.toWorld(v)), v);
  }
}

}  // namespace
}  // namespace pathfarm
