#pragma once
// The lens perturbation of Veach and Guibas 1997 (Veach 1997, section 11.4.3): the film
// position of x0 -> x1 moves by a small offset (PerturbationSize: 0.1 pixel to a tenth of
// the image width, uniform angle); the new camera ray regenerates x1 and, through the
// specular chain x1 ... x_c-1 (the same Dirac lobes), the first non-delta vertex x_c,
// which is reconnected to x_c+1 (or is the new light end when c = k).
//
// T(X -> Y) = p(offset) W H p_cam(x0 -> y1) R_cam(y chain 0 .. c), where W H p_cam is the
// area density of y1 for a film position with unit density per pixel (p_cam is the
// camera's density over the whole film, path_walk.h) and R_cam the chain's
// regeneration density (specular_chain.h). The offset density is symmetric.
#include "renderer/metropolis/path_space/path_mutation.h"
#include "renderer/sampling/sample_stream.h"

namespace pathfarm {

// The move to the film position current.contribution.film + offset (pixels).
PathMutation lensPerturbation(const WindowScene& scene, const PathSpaceState& current, Vec2f offset);
// The random move.
PathMutation lensPerturbation(const WindowScene& scene, const PathSpaceState& current, SampleStream& random);

}  // namespace pathfarm
