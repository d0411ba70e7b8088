// The reconnection shift on a test path: its Jacobian against finite differences of the
// map it stands for, and the inverse shift leading back.
#include "renderer/integrators/shift_mapping.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pathfarm {
namespace {

struct V3 {
  double x, y, z;
  V3 operator+(V3 o) const { return {x + o.x, y + o.y, z + o.z}; }
  V3 operator-(V3 o) const { return {x - o.x, y - o.y, z - o.z}; }
  V3 operator*(double s) const { return {x * s, y * s, z * s}; }
};
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
V3 unit(V3 a) { return a * (1 / std::sqrt(dot(a, a))); }
Vec3f toFloat(V3 a) { return {static_cast<float>(a.x), static_cast<float>(a.y), static_cast<float>(a.z)}; }

// A test path: base vertex, offset vertex, and the shared vertex on a tilted plane.
const V3 kBase{0, 0, 0}, kOffset{0.3, 0.12, -0.05}, kShared{0.2, 0.1, 2}, kNormal = unit({0.3, 0.2, -1});

SurfaceHit sharedHit() {
  SurfaceHit hit;
  hit.position = toFloat(kShared);
  hit.geometricNormal = toFloat(kNormal);
  hit.shadingNormal = hit.geometricNormal;
  return hit;
}

// The map the reconnection stands for: a base direction from kBase hits the plane, and the
// offset direction from kOffset aims at that point.
V3 offsetDirection(V3 baseDirection) {
  const double t = dot(kShared - kBase, kNormal) / dot(baseDirection, kNormal);
  return unit(kBase + baseDirection * t - kOffset);
}

TEST(ShiftMapping, ReconnectionJacobianMatchesFiniteDifferences) {
  const V3 w0 = unit(kShared - kBase);
  const V3 e1 = unit(cross(w0, {0, 1, 0})), e2 = cross(w0, e1);
  const double h = 1e-5;
  // Solid angle ratio of a small patch of directions around w0 and its image.
  const auto direction = [&](double a, double b) { return unit(w0 + e1 * a + e2 * b); };
  const V3 da = direction(h, 0) - direction(-h, 0), db = direction(0, h) - direction(0, -h);
  const V3 ia = offsetDirection(direction(h, 0)) - offsetDirection(direction(-h, 0));
  const V3 ib = offsetDirection(direction(0, h)) - offsetDirection(direction(0, -h));
  const double numeric = std::sqrt(dot(cross(ia, ib), cross(ia, ib))) / std::sqrt(dot(cross(da, db), cross(da, db)));

  const auto link = reconnect(toFloat(kOffset), toFloat(kBase), sharedHit());
  ASSERT_TRUE(link);
  EXPECT_NEAR(link->jacobian, numeric, 1e-4 * numeric);
  EXPECT_GT(std::abs(numeric - 1), 0.01);  // a path where the Jacobian matters
  const V3 expected = unit(kShared - kOffset);
  EXPECT_NEAR(link->direction.x, expected.x, 1e-6);
  EXPECT_NEAR(link->direction.y, expected.y, 1e-6);
  EXPECT_NEAR(link->direction.z, expected.z, 1e-6);
}

TEST(ShiftMapping, InverseShiftLeadsBack) {
  const auto forward = reconnect(toFloat(kOffset), toFloat(kBase), sharedHit());
  const auto back = reconnect(toFloat(kBase), toFloat(kOffset), sharedHit());
  ASSERT_TRUE(forward && back);
  EXPECT_NEAR(forward->jacobian * back->jacobian, 1.0, 1e-6);
  const V3 original = unit(kShared - kBase);
  EXPECT_NEAR(back->direction.x, original.x, 1e-6);
  EXPECT_NEAR(back->direction.y, original.y, 1e-6);
  EXPECT_NEAR(back->direction.z, original.z, 1e-6);
  // From the far side of the shared surface there is no shift.
  const V3 behind = kShared - kNormal * 0.5;
  EXPECT_FALSE(reconnect(toFloat(behind), toFloat(kBase), sharedHit()));
}

}  // namespace
}  // namespace pathfarm
