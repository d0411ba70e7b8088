#include "renderer/accel/triangle_bvh.h"

#include <algorithm>
#include <numeric>

namespace pathfarm {
namespace {

constexpr uint32_t kLeafSize = 4;

Vec3d lowest(Vec3d a, Vec3d b) { return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)}; }
Vec3d highest(Vec3d a, Vec3d b) { return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}; }

}  // namespace

TriangleBvh::TriangleBvh(const TriangleMesh& mesh) {
  const size_t n = mesh.triangleCount();
  if (n == 0) return;
  std::vector<Vec3d> centroids(n), lower(n), upper(n);
  for (size_t t = 0; t < n; ++t) {
    const Vec3d a(mesh.positions[mesh.indices[3 * t]]), b(mesh.positions[mesh.indices[3 * t + 1]]),
        c(mesh.positions[mesh.indices[3 * t + 2]]);
    lower[t] = lowest(a, lowest(b, c));
    upper[t] = highest(a, highest(b, c));
    centroids[t] = (a + b + c) / 3;
  }
  order_.resize(n);
  std::iota(order_.begin(), order_.end(), 0u);
  nodes_.reserve(2 * n);
  build(centroids, lower, upper, 0, static_cast<uint32_t>(n));
}

// Median split along the widest axis of the centroids; depth stays near log2(n), far
// below the traversal stack's 64.
uint32_t TriangleBvh::build(const std::vector<Vec3d>& centroids, const std::vector<Vec3d>& lower,
                            const std::vector<Vec3d>& upper, uint32_t first, uint32_t count) {
  const auto index = static_cast<uint32_t>(nodes_.size());
  nodes_.emplace_back();
  Node node;
  node.lower = lower[order_[first]];
  node.upper = upper[order_[first]];
  Vec3d centroidLower = centroids[order_[first]], centroidUpper = centroidLower;
  for (uint32_t i = first; i < first + count; ++i) {
    node.lower = lowest(node.lower, lower[order_[i]]);
    node.upper = highest(node.upper, upper[order_[i]]);
    centroidLower = lowest(centroidLower, centroids[order_[i]]);
    centroidUpper = highest(centroidUpper, centroids[order_[i]]);
  }
  if (count <= kLeafSize) {
    node.first = first;
    node.count = count;
    nodes_[index] = node;
    return index;
  }
  const Vec3d extent = centroidUpper - centroidLower;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  const uint32_t half = count / 2;
  std::nth_element(order_.begin() + first, order_.begin() + first + half, order_.begin() + first + count,
                   [&](uint32_t a, uint32_t b) { return centroids[a][axis] < centroids[b][axis]; });
  build(centroids, lower, upper, first, half);
  node.right = build(centroids, lower, upper, first + half, count - half);
  nodes_[index] = node;
  return index;
}

bool TriangleBvh::crosses(const Node& node, Vec3d o, Vec3d inverse, double minDistance, double maxDistance) const {
  // Slabs, with the box grown by a rounding's worth so that hits on its faces count.
  const double pad = 1e-9 * (1 + maxAbs(node.upper - node.lower));
  double near = minDistance, far = maxDistance;
  for (int axis = 0; axis < 3; ++axis) {
    double a = (node.lower[axis] - pad - o[axis]) * inverse[axis];
    double b = (node.upper[axis] + pad - o[axis]) * inverse[axis];
    if (a > b) std::swap(a, b);
    // A ray parallel to the slab gives NaN (0 * inf) when its origin is on a face: keep it.
    if (!(a <= b)) continue;
    near = std::max(near, a);
    far = std::min(far, b);
  }
  return near <= far;
}

}  // namespace pathfarm
