#pragma once
// One glTF mesh primitive as a triangle mesh: positions, unit normals and the chosen
// TEXCOORD set, transformed (KHR_texture_transform), then v flipped to pathfarm's
// convention (v = 1 at the image's top), indexed
// or not, triangle strips and fans unrolled. Zero-area triangles are dropped (they
// carry no light); NaN positions, degenerate normals and indices past the vertices are
// refused.
#include <array>
#include <memory>
#include <tuple>

#include "renderer/scene/gltf/gltf_document.h"
#include "renderer/scene/mesh.h"

namespace pathfarm {

// Which TEXCOORD set a primitive's textures read, and the KHR_texture_transform applied
// to it in glTF's uv space: u' = m[0] u + m[1] v + m[2], v' = m[3] u + m[4] v + m[5].
struct TextureCoordinates {
  int set = 0;
  std::array<float, 6> m{1, 0, 0, 0, 1, 0};

  bool operator<(const TextureCoordinates& o) const { return std::tie(set, m) < std::tie(o.set, o.m); }
  bool operator==(const TextureCoordinates& o) const { return set == o.set && m == o.m; }
};

// Nothing (after a warning) for primitives without area: points, lines, or only
// degenerate triangles.
std::shared_ptr<const TriangleMesh> importPrimitive(const GltfDocument& document, int mesh, int primitive,
                                                    const TextureCoordinates& coordinates);

}  // namespace pathfarm
