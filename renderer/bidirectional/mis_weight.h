#pragma once
// Multiple importance sampling over the strategies of bidirectional path tracing
// (Veach 1997, section 10.3; power heuristic with exponent 2).
//
// A path x0 ... xk can be sampled by the strategies t = 1 ... k+1 (t camera vertices,
// s = k + 1 - t light vertices); t = 0 (a light subpath hitting the lens) is never used.
// Its density under strategy t is
//   p_t = prod_{0 < i < t} fromCamera[i] * prod_{i >= t} fromLight[i],
// where fromCamera[i] is the density of x_i sampled from x_i-1 walking from the camera,
// fromLight[i] that of x_i sampled from x_i+1 walking from the light (fromLight[k]: the
// light end's own density). The lens density is common to every strategy and left out.
// A density sampled from a delta vertex is the same Dirac on both sides and counts as 1.
// Strategy t is possible when s = 0, or when x_t-1 and x_t are both non-delta, except
// that a path ending on the environment is sampled only by s = 0 and by s = 1 with t >= 2
// (light subpaths do not leave the environment, subpath.h).
#include <cstddef>
#include <vector>

namespace pathfarm {

struct PathDensities {
  std::vector<float> fromCamera, fromLight;  // k + 1 entries each
  std::vector<bool> delta;                   // per vertex
  bool environmentEnd = false;

  int vertexCount() const { return static_cast<int>(delta.size()); }
  void resize(int vertices);
};

bool strategyPossible(const PathDensities& path, int t);
// p_t as above; 0 for an impossible strategy.
double strategyDensity(const PathDensities& path, int t);
// The power-heuristic weight of strategy t among the possible ones; 0 if t is impossible.
float misWeight(const PathDensities& path, int t);

}  // namespace pathfarm
