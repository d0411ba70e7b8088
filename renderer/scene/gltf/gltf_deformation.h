#pragma once
// The skin and morph targets of one glTF mesh primitive placed by one node, as a
// MeshDeformation: skinning with any number of JOINTS_n/WEIGHTS_n sets (weights
// normalized per vertex), morph targets of POSITION, NORMAL and TANGENT with the node's
// (or mesh's) default weights and its animated `weights` channel. Refuses, with the JSON
// pointer, a joint outside the skin, a vertex without weight and mismatched counts.
#include <memory>

#include "renderer/scene/gltf/gltf_animation.h"
#include "renderer/scene/gltf/gltf_document.h"
#include "renderer/scene/mesh_deformation.h"

namespace pathfarm {

// Null when the node's primitive neither is skinned nor has morph targets.
std::shared_ptr<const MeshDeformation> importDeformation(const GltfDocument& document,
                                                         const GltfNodeAnimation& animation, int node,
                                                         int primitive, std::shared_ptr<const TriangleMesh> mesh);

}  // namespace pathfarm
