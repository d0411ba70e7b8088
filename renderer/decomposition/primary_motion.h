#pragma once
// Screen-space motion of what a pixel sees: the visible point's object-space position
// carried to a neighbouring frame's object transform and projected with that frame's
// camera, at the same point of the shutter (Zimmer et al. 2015, Section 4). The
// background moves with the camera alone.
#include <optional>

#include "renderer/accel/frame_geometry.h"
#include "renderer/scene/camera.h"

namespace pathfarm {

// Pixels moved to the frame `forward` frames on and from the frame `backward` frames
// back (MotionSpan); nothing where the point's image is behind the camera in one of them.
struct MotionPair {
  std::optional<Vec2f> forward, backward;
};

// How many frames away the motion vectors reach: the neighbouring frames by default, the
// neighbouring keyframes in a keyframe render. Motion over a span is computed directly,
// not chained frame by frame, so a point hidden in the frames between keeps its motion.
struct MotionSpan {
  int forward = 1;
  int backward = 1;
};

// The camera's placements at one point of the shutter in this frame and in the frames
// the motion reaches. A renderer keeps them per shutter bucket: evaluating the camera's
// animation is most of the cost of projecting a point.
struct CameraPlacements {
  const Transform& now;  // the placement that made the sample's camera ray
  const Transform& forward;
  const Transform& backward;
};

class PrimaryMotion {
 public:
  PrimaryMotion(const FrameGeometry& geometry, const Camera& camera, int64_t frame, MotionSpan span = {})
      : geometry_(geometry), camera_(camera), frame_(frame), span_(span) {}

  // The point `hit` saw at shutter time `time`.
  MotionPair ofSurface(const SurfaceHit& hit, float time) const;
  // The environment seen along `direction`.
  MotionPair ofBackground(Vec3f direction, float time) const;
  // The same, with the camera's placements at `time` given.
  MotionPair ofSurface(const SurfaceHit& hit, float time, const CameraPlacements& camera) const;
  MotionPair ofBackground(Vec3f direction, const CameraPlacements& camera) const;

 private:
  // The camera's placement at `time` of the frame `offset` frames from this one.
  Transform cameraAt(float time, int offset) const;

  const FrameGeometry& geometry_;
  const Camera& camera_;
  int64_t frame_;
  MotionSpan span_;
};

}  // namespace pathfarm
