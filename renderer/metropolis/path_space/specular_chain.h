#pragma once
// Specular chains of a complete path: maximal runs of delta vertices x_a+1 ... x_b-1
// between two non-delta vertices x_a and x_b. Their positions are not free: given x_a and
// x_a+1 (or x_b and x_b-1), the Dirac lobes fix every direction, so a perturbation that
// moves any of them re-traces the chain and regenerates the vertices it lands on.
//
// Densities. A re-traced chain regenerates vertices with a Dirac density; as in Veach
// 1997 (section 11.4) it is written as the formal area density of the regenerated
// vertices, the product of the geometry terms g(prev, x) = |cos at x| / |x - prev|^2 of
// the edges that reach them, the lobe's own factor being the same in both directions and
// cancelling against f's. Traced from the camera side, the free coordinates are (x_a,
// x_a+1) and the density of the rest is R_cam = prod_{a+1 < j <= b} g(x_j-1, x_j): then
// f(X) / R_cam is the path's density in the measure dA(x_a) dA(x_a+1), because f holds
// every edge's g and the Dirac lobe removes exactly those after x_a+1. Traced from the
// light side, the free coordinates are (x_b-1, x_b); by the conservation of etendue,
//   n_a^2 G(x_a, x_a+1) dA(x_a) dA(x_a+1) = n_b^2 G(x_b-1, x_b) dA(x_b-1) dA(x_b)
// (G the symmetric geometry term |cos cos| / d^2, n the refractive index of the medium
// of the edge), so R_light = R_cam n_a^2 G(x_a, x_a+1) / (n_b^2 G(x_b-1, x_b)). For
// mirrors this is prod_{a <= j < b-1} g(x_j+1, x_j), the same rule walking the other way.
#include <optional>
#include <vector>

#include "renderer/bidirectional/bdpt_scene.h"
#include "renderer/bidirectional/complete_path.h"

namespace pathfarm {

struct SpecularChain {
  int a = 0, b = 0;  // the non-delta ends; x_a+1 ... x_b-1 are delta, b >= a + 2
};

enum class ChainDirection { FromCamera, FromLight };

// The path's specular chains, from the camera to the light.
std::vector<SpecularChain> specularChainsOf(const std::vector<PathVertex>& x);

// Re-traces `chain` of `vertices` in `direction`: from the anchor (x_a from the camera,
// x_b from the light) through its neighbour in the chain, both already where they
// belong in `vertices`, reflecting or refracting by the same Dirac lobes as in
// `original` (the path before the move), and replaces the vertices it reaches up to the
// far end. False when the re-traced chain does not have the original's vertex types (a
// ray misses, an edge is blocked, a surface lacks the lobe, the far end lands on a
// surface of another kind, or would have to land on the lens point).
bool retraceChain(const BdptScene& bdpt, float time, const std::vector<PathVertex>& original, SpecularChain chain,
                  ChainDirection direction, std::vector<PathVertex>& vertices);

// Bidirectional sampling leaves a chain consistent only to the ray offsets of its walk
// (about 1e-4 in direction), but a perturbation must be undone exactly by its reverse:
// re-traces every chain of x from the camera side so that its Dirac lobes hold exactly.
// False (x partly re-traced) when a chain cannot be re-traced.
bool straightenChains(const BdptScene& bdpt, float time, std::vector<PathVertex>& x);

// R_cam or R_light above for the chain of the vertex list x.
double regenerationDensity(const Scene& scene, const std::vector<PathVertex>& x, SpecularChain chain,
                           ChainDirection direction);

// The vertex that the ray from `from` along unit `direction` regenerates in place of
// `wanted` (its hit, or an environment direction when it escapes), if it is of the same
// kind: the same vertex type and delta flag, on an object that is animated if and only if
// wanted's is, and connectible where wanted is a non-delta surface vertex. The hit is
// put on the ray from from's exact position (the ray itself leaves from an offset
// origin), so that regenerating the other way comes back to the same points.
std::optional<PathVertex> regenerate(const BdptScene& bdpt, float time, const PathVertex& from, Vec3f direction,
                                     const PathVertex& wanted);

// Whether the edge between two vertices of a path is unoccluded, as measure() tests it.
bool edgeVisible(const BdptScene& bdpt, float time, const PathVertex& cameraSide, const PathVertex& lightSide);

}  // namespace pathfarm
