#pragma once
// Temporal manifold exploration (Zimmer et al. 2015, Section 4.1), after the manifold
// walk of Jakob and Marschner 2012. A specular path is constrained at every specular
// vertex: the generalized half vector eta_i wi + eta_o wo, projected on the tangent
// plane, vanishes (eta = 1 for reflection). Its endpoints are attached to the camera and
// to a point of the non-specular object, both moving with time. The walk advances time
// in adaptive steps and, at each, moves the path until its endpoint is back on that
// object point; every step extrapolates along the constraint manifold's tangent and
// projects back onto the manifold by re-tracing from the camera through the chain.
#include <optional>

#include "renderer/decomposition/specular_chain.h"

namespace pathfarm {

// How the first specular vertex's surface coordinates (u1, v1) change with the
// endpoint's (un, vn) and with time: two rows of T = -Jc^-1 (dc/dun, dc/dvn, dc/dt) by
// the implicit function theorem. The pinhole has no surface coordinates of its own; its
// motion enters through dc/dt.
struct FirstVertexTangent {
  double du[3], dv[3];  // d(u1)/d(un, vn, t) and d(v1)/d(un, vn, t), t in seconds
};

// The tangent at `path`; nothing when the constraint Jacobian Jc is singular (grazing
// incidence, a degenerate surface) or anything is not finite.
std::optional<FirstVertexTangent> manifoldTangent(const ChainPath& path, const SpecularChain& chain);

// Iterations spent: time steps (outer) and manifold steps (inner, one re-trace each).
struct WalkCounts {
  int inner = 0, outer = 0;
};

// Follows `start` to `targetSeconds` keeping its endpoint on the object point it starts
// on. Nothing when the path ceases to exist, changes the sides it meets its surfaces
// from, or the iteration bounds are reached. The result's endpoint lies within
// kWalkTolerance * (1 + its largest coordinate) of the object point. Pure: the same
// arguments give the same bits.
std::optional<ChainPath> walkInTime(const ChainTracer& tracer, const ChainPath& start, double targetSeconds,
                                    WalkCounts& counts);

inline constexpr double kWalkTolerance = 1e-7;

}  // namespace pathfarm
