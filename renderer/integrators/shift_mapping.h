#pragma once
// The shift of gradient-domain path tracing (Kettunen et al. 2015, Section 5.2), in the
// "hybrid" form: an offset path starts through the neighbouring pixel with the base
// path's film jitter, time and lens sample, and then
//   - replays the base path's random numbers at its own vertices (a primary-sample-space
//     shift: Jacobian = base density / offset density, for delta lobes too) until
//   - the base vertex x_k and the offset vertex y_k are both connectable and so is the
//     base's next vertex x_k+1 (or the base escapes to the environment): the offset then
//     connects y_k to x_k+1 and shares every later vertex of the base path.
// A vertex is connectable when every lobe of its BSDF is rough (non-delta, symbol D), so
// any outgoing direction can be evaluated there. This replaces the paper's half-vector
// copy through specular chains by replay, which is exact and invertible for every lobe.
#include <optional>

#include "renderer/accel/surface_hit.h"
#include "renderer/materials/bsdf.h"

namespace pathfarm {

bool isConnectable(const Bsdf& bsdf);

// Connecting the offset vertex `from` to the base vertex `target` that the base reached
// from `baseFrom`.
struct Reconnection {
  Vec3f direction;  // unit, from `from` towards the target
  float distance;
  // d omega_offset / d omega_base: the solid angle at `from` that the base's solid angle
  // at `baseFrom` maps to through the shared vertex, (cos' / d'^2) / (cos / d^2).
  float jacobian;
};

// Nothing when the two arrive on different sides of the target's surface or the target
// is seen edge-on.
std::optional<Reconnection> reconnect(Vec3f from, Vec3f baseFrom, const SurfaceHit& target);

}  // namespace pathfarm
