#pragma once
// Where a ray met the scene, in world space, with what shading needs.
#include <cstdint>

#include "renderer/math/vecmath.h"

namespace pathfarm {

struct SurfaceHit {
  float distance = 0;
  Vec3f position;
  Vec3f shapePosition;    // the same point in the space of the object's prepared shape
  Vec3f geometricNormal;  // unit, facing out of the shape (the side that emits)
  Vec3f shadingNormal;    // unit, interpolated where the mesh has normals
  Vec2f uv;
  int object = -1;        // index into Scene::objects
  uint32_t primitive = 0;
  // Where in triangle `primitive` (Embree's u, v): how a point on a deforming mesh is
  // found again at another time.
  Vec2f barycentric;
};

}  // namespace pathfarm
