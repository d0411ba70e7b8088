#pragma once
// The caustic perturbation of Veach and Guibas 1997 (Veach 1997, section 11.4.3), for
// paths whose camera sees a non-delta vertex x1 lit through a (possibly empty) specular
// chain x2 ... x_j-1 from the non-delta vertex x_j: the direction from x_j towards x_j-1
// turns by a small angle (PerturbationSize: 1e-4 to 0.1 radians, uniform around it), the
// new ray regenerates x_j-1 and, back through the same Dirac lobes, the chain down to a
// new x1, which is reconnected to the camera.
//
// T(X -> Y) = p(angle) / (2 pi sin(angle)) g(x_j, y_j-1) R_light(y chain 1 .. j), the
// first factor the symmetric solid-angle density of the turned direction, g its
// conversion to area at y_j-1 and R_light the chain's regeneration density
// (specular_chain.h). Paths without such a vertex x_j (x1 delta, or x_j the
// environment) are not perturbed: the proposal fails.
#include "renderer/metropolis/path_space/path_mutation.h"
#include "renderer/sampling/sample_stream.h"

namespace pathfarm {

// The index j above, or -1 when the path has none.
int causticSource(const std::vector<PathVertex>& x);

// The move that sends x_j's ray along the unit `direction`.
PathMutation causticPerturbation(const WindowScene& scene, const PathSpaceState& current, Vec3f direction);
// The random move.
PathMutation causticPerturbation(const WindowScene& scene, const PathSpaceState& current, SampleStream& random);

}  // namespace pathfarm
