#include "renderer/scene/mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>
#include <utility>

namespace pathfarm {
namespace {

Vec3f corner(const TriangleMesh& m, size_t tri, int k) {
  return m.positions[m.indices[3 * tri + static_cast<size_t>(k)]];
}

Vec3f geometricNormal(const TriangleMesh& m, size_t tri) {
  return cross(corner(m, tri, 1) - corner(m, tri, 0), corner(m, tri, 2) - corner(m, tri, 0));
}

double totalArea(const TriangleMesh& m) {
  double area = 0;
  for (size_t t = 0; t < m.triangleCount(); ++t) area += 0.5 * length(geometricNormal(m, t));
  return area;
}

// Every vertex normal of a triangle agrees with the normalized winding normal.
void expectWindingMatchesNormals(const TriangleMesh& m) {
  ASSERT_EQ(m.normals.size(), m.positions.size());
  for (size_t t = 0; t < m.triangleCount(); ++t) {
    const Vec3f g = normalize(geometricNormal(m, t));
    for (int k = 0; k < 3; ++k) {
      const Vec3f n = m.normals[m.indices[3 * t + static_cast<size_t>(k)]];
      EXPECT_NEAR(length(n), 1.0f, 1e-6f);
      EXPECT_NEAR(dot(g, n), 1.0f, 1e-5f) << "triangle " << t << " corner " << k;
    }
  }
}

void expectValidIndices(const TriangleMesh& m) {
  ASSERT_EQ(m.indices.size() % 3, 0u);
  for (uint32_t i : m.indices) ASSERT_LT(i, m.positions.size());
}

TEST(MakeRectangle, CountsAndExtents) {
  const TriangleMesh m = makeRectangle(3.0f, 2.0f);
  EXPECT_EQ(m.positions.size(), 4u);
  EXPECT_EQ(m.normals.size(), 4u);
  EXPECT_EQ(m.uvs.size(), 4u);
  EXPECT_EQ(m.triangleCount(), 2u);
  expectValidIndices(m);
  for (const Vec3f& p : m.positions) {
    EXPECT_FLOAT_EQ(std::abs(p.x), 1.5f);
    EXPECT_FLOAT_EQ(std::abs(p.y), 1.0f);
    EXPECT_FLOAT_EQ(p.z, 0.0f);
  }
}

TEST(MakeRectangle, AreaAndNormalsPointUp) {
  const TriangleMesh m = makeRectangle(3.0f, 2.0f);
  EXPECT_NEAR(totalArea(m), 6.0, 1e-6);
  expectWindingMatchesNormals(m);
  for (const Vec3f& n : m.normals) EXPECT_EQ(n, (Vec3f{0, 0, 1}));
  for (size_t t = 0; t < m.triangleCount(); ++t) EXPECT_GT(geometricNormal(m, t).z, 0.0f);
}

TEST(MakeRectangle, UvsSpanUnitSquareAlongAxes) {
  const TriangleMesh m = makeRectangle(4.0f, 1.0f);
  for (size_t i = 0; i < m.positions.size(); ++i) {
    // u grows with x, v grows with y, (0,0) at the (-x,-y) corner.
    EXPECT_FLOAT_EQ(m.uvs[i].x, m.positions[i].x > 0 ? 1.0f : 0.0f);
    EXPECT_FLOAT_EQ(m.uvs[i].y, m.positions[i].y > 0 ? 1.0f : 0.0f);
  }
}

TEST(MakeBox, CountsAndExtents) {
  const Vec3f size{2.0f, 3.0f, 5.0f};
  const TriangleMesh m = makeBox(size);
  EXPECT_EQ(m.positions.size(), 24u);
  EXPECT_EQ(m.normals.size(), 24u);
  EXPECT_EQ(m.uvs.size(), 24u);
  EXPECT_EQ(m.triangleCount(), 12u);
  expectValidIndices(m);
  for (const Vec3f& p : m.positions) {
    EXPECT_FLOAT_EQ(std::abs(p.x), 1.0f);
    EXPECT_FLOAT_EQ(std::abs(p.y), 1.5f);
    EXPECT_FLOAT_EQ(std::abs(p.z), 2.5f);
  }
  for (const Vec2f& uv : m.uvs) {
    EXPECT_TRUE(uv.x == 0.0f || uv.x == 1.0f);
    EXPECT_TRUE(uv.y == 0.0f || uv.y == 1.0f);
  }
}

TEST(MakeBox, AreaVolumeAndOutwardNormals) {
  const Vec3f size{2.0f, 3.0f, 5.0f};
  const TriangleMesh m = makeBox(size);
  EXPECT_NEAR(totalArea(m), 2.0 * (2 * 3 + 3 * 5 + 5 * 2), 1e-5);
  expectWindingMatchesNormals(m);

  // Outward: the normal points away from the center, and the vertex lies on the face
  // plane the normal names.
  for (size_t i = 0; i < m.positions.size(); ++i) {
    const Vec3f n = m.normals[i];
    const Vec3f p = m.positions[i];
    EXPECT_GT(dot(n, p), 0.0f);
    const Vec3f half = size * 0.5f;
    EXPECT_FLOAT_EQ(dot(n, p), std::abs(dot(n, half)));
  }

  // Divergence theorem: with outward winding the signed volume is the box volume.
  double volume = 0;
  for (size_t t = 0; t < m.triangleCount(); ++t) {
    volume += dot(corner(m, t, 0), cross(corner(m, t, 1), corner(m, t, 2))) / 6.0;
  }
  EXPECT_NEAR(volume, 2.0 * 3.0 * 5.0, 1e-4);
}

TEST(MakeBox, IsClosedAndConsistentlyWound) {
  const TriangleMesh m = makeBox({1.0f, 1.0f, 1.0f});
  // Faces have their own vertices, so edges are compared by position.
  using Key = std::tuple<float, float, float>;
  auto key = [](Vec3f p) { return Key{p.x, p.y, p.z}; };
  std::map<std::pair<Key, Key>, int> directed;
  std::map<std::pair<Key, Key>, int> undirected;
  for (size_t t = 0; t < m.triangleCount(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const Key a = key(corner(m, t, k));
      const Key b = key(corner(m, t, (k + 1) % 3));
      ASSERT_NE(a, b) << "degenerate edge";
      ++directed[{a, b}];
      ++undirected[{std::min(a, b), std::max(a, b)}];
    }
  }
  // 12 box edges + 6 face diagonals.
  EXPECT_EQ(undirected.size(), 18u);
  for (const auto& [edge, count] : undirected) EXPECT_EQ(count, 2);
  // Consistent orientation: each directed edge is used once, its reverse by the neighbor.
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(directed.count({edge.second, edge.first}), 1u);
  }
}

TEST(MakeBox, NegativeSizeKeepsOutwardWinding) {
  const TriangleMesh m = makeBox({-1.0f, 2.0f, 1.0f});
  expectWindingMatchesNormals(m);
  EXPECT_NEAR(totalArea(m), 2.0 * (2 + 2 + 1), 1e-5);
}

}  // namespace
}  // namespace pathfarm
