#pragma once
// The temporal perturbation of Van de Woestijne et al. 2017: a path moved to another
// time of the window.
//
// Given X at tau, propose tau' from the temporal proposal (temporal_proposal.h; a closed
// shutter at tau' means f = 0, and the proposal is rejected). Every vertex on an animated
// object moves with it to tau' and the camera vertex with the camera; static vertices
// stay (vertex_motion.h). A specular chain with a moved vertex, or whose anchor moved, is
// re-traced from its anchor through the same Dirac lobes and regenerates the vertices it
// lands on (specular_chain.h). All chains are re-traced from the camera (walking
// towards the light, each chain anchored on the previous one's result) or all from the
// light: one way chosen with probability 1/2, the other tried if it fails. The remaining
// edges are reconnected: measure() tests every edge's visibility. The move fails when a
// chain cannot be re-traced with the same vertex types; the path's length never changes.
//
// Transition density (the paper's Eq. 2, in the area measure of Y's vertices, with the
// Dirac factors that appear alike in both directions left out):
//   T(X -> Y) = p_time(tau -> tau') * q * prod_{re-traced chains} R_way(Y)
//               * prod_{moved, not regenerated vertices v} 1 / (dA_world / dA_shape)(v, tau')
// where q = 1/2 if both ways succeed from X at tau' and 1 if only the way used does (or
// no chain is re-traced), R_way the chain's regeneration density for the way used, and
// the last factor the Jacobian of moving a vertex with its object (1 for rigid motion).
// The move is its own inverse: from Y at tau' the same way back to tau gives X again, so
// T(Y -> X) is the same formula evaluated for that reverse move.
#include "renderer/metropolis/chain_target.h"
#include "renderer/metropolis/path_space/path_mutation.h"
#include "renderer/metropolis/path_space/specular_chain.h"

namespace pathfarm {

struct TemporalMove {
  PathMutation mutation;
  ChainDirection way = ChainDirection::FromCamera;  // the way the chains were re-traced
  bool retraced = false;    // whether any chain was re-traced
};

// The move of `current` to `tauNext`, trying the way `first` first. `proposal` gives
// p_time in both directions.
TemporalMove temporalMove(const WindowScene& scene, const TemporalProposal& proposal, const PathSpaceState& current,
                          double tauNext, ChainDirection first);

// The random move: tau' from the chain's temporal proposal, then the first way.
TemporalMove perturbInTime(const WindowScene& scene, const PathSpaceState& current, MutationContext& context);

}  // namespace pathfarm
