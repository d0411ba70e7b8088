#pragma once
// A deforming mesh's poses across one frame's shutter, at uniformly spaced instants that
// Embree's multi-segment motion blur blends linearly per vertex. A turning joint moves
// vertices on arcs, so a segment's chord strays from the true path by its sagitta, which
// shrinks with the square of the segment's length: the pose at mid-shutter measures that
// stray for one segment, and the instants are as few as keep it within
// kShutterPoseTolerance of the mesh's extent. Multi-segment BVHs cost about their
// segment count to build, and most frames of most characters need one segment.
#include <vector>

#include "renderer/scene/mesh_deformation.h"

namespace pathfarm {

// Of the posed mesh's bounding-box diagonal: the furthest a blended vertex may stray from
// its true path during the shutter.
constexpr float kShutterPoseTolerance = 1e-3f;

// One pose at `open` when the shutter is closed (close <= open); else 2, 3, 5 or 9 from
// `open` to `close`.
std::vector<MeshDeformation::Pose> shutterPoses(const MeshDeformation& deformation, double open, double close);

}  // namespace pathfarm
