#pragma once
// One glTF mesh primitive as a triangle mesh: positions, unit normals and the chosen
// TEXCOORD set (v flipped to pathfarm's convention, v = 1 at the image's top), indexed
// or not, triangle strips and fans unrolled. Zero-area triangles are dropped (they
// carry no light); NaN positions, degenerate normals and indices past the vertices are
// refused.
#include <memory>

#include "renderer/scene/gltf/gltf_document.h"
#include "renderer/scene/mesh.h"

namespace pathfarm {

// Nothing (after a warning) for primitives without area: points, lines, or only
// degenerate triangles.
std::shared_ptr<const TriangleMesh> importPrimitive(const GltfDocument& document, int mesh, int primitive,
                                                    int texCoord);

}  // namespace pathfarm
