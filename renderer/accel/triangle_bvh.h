#pragma once
// A bounding volume hierarchy over one mesh's triangles in double precision, for exact
// re-tracing against a single object (the specular manifold walk re-traces its chain
// many times per pixel; testing every triangle would make large meshes unusable).
#include <cstdint>
#include <vector>

#include "renderer/math/vec3d.h"
#include "renderer/scene/mesh.h"

namespace pathfarm {

class TriangleBvh {
 public:
  explicit TriangleBvh(const TriangleMesh& mesh);

  // Calls visit(triangle) for every triangle whose bounds the ray o + s d meets with s in
  // (minDistance, maxDistance); `maxDistance` is read again at every node, so the visitor
  // narrows the search by lowering it.
  template <class Visit>
  void forEachCandidate(Vec3d o, Vec3d d, double minDistance, const double& maxDistance, Visit visit) const;

 private:
  struct Node {
    Vec3d lower, upper;
    uint32_t first = 0, count = 0;  // a leaf's triangles in order_; count 0: an inner node
    uint32_t right = 0;             // an inner node's second child (the first follows it)
  };
  uint32_t build(const std::vector<Vec3d>& centroids, const std::vector<Vec3d>& lower, const std::vector<Vec3d>& upper,
                 uint32_t first, uint32_t count);
  bool crosses(const Node& node, Vec3d o, Vec3d inverse, double minDistance, double maxDistance) const;

  std::vector<Node> nodes_;
  std::vector<uint32_t> order_;
};

template <class Visit>
void TriangleBvh::forEachCandidate(Vec3d o, Vec3d d, double minDistance, const double& maxDistance, Visit visit) const {
  if (nodes_.empty()) return;
  const Vec3d inverse{1 / d.x, 1 / d.y, 1 / d.z};
  uint32_t stack[64];
  int size = 0;
  stack[size++] = 0;
  while (size > 0) {
    const Node& node = nodes_[stack[--size]];
    if (!crosses(node, o, inverse, minDistance, maxDistance)) continue;
    if (node.count > 0) {
      for (uint32_t i = node.first; i < node.first + node.count; ++i) visit(order_[i]);
    } else if (size + 2 <= 64) {
      stack[size++] = node.right;
      stack[size++] = static_cast<uint32_t>(&node - nodes_.data()) + 1;
    }
  }
}

}  // namespace pathfarm
