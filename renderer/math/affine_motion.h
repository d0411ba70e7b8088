#pragma once
// An affine placement x -> linear * x + translation at one instant, in double precision,
// with its rate of change per second: what differentiating through an animation needs
// (the velocity of a point attached to a moving object, the turning of its normals).
#include "renderer/math/vec3d.h"

namespace pathfarm {

struct AffineMotion {
  Mat3d linear = Mat3d::identity();
  Vec3d translation;
  Mat3d linearRate;       // d(linear)/dt
  Vec3d translationRate;  // d(translation)/dt

  Vec3d point(Vec3d p) const { return linear * p + translation; }
  Vec3d vector(Vec3d v) const { return linear * v; }
  // The velocity of the world point that sits at object-space `p`.
  Vec3d velocity(Vec3d p) const { return linearRate * p + translationRate; }
};

}  // namespace pathfarm
