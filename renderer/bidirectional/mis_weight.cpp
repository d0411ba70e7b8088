#include "renderer/bidirectional/mis_weight.h"

namespace pathfarm {

void PathDensities::resize(int vertices) {
  fromCamera.assign(static_cast<std::size_t>(vertices), 0.0f);
  fromLight.assign(static_cast<std::size_t>(vertices), 0.0f);
  delta.assign(static_cast<std::size_t>(vertices), false);
}

bool strategyPossible(const PathDensities& path, int t) {
  const int k = path.vertexCount() - 1;
  const int s = k + 1 - t;
  if (t < 1 || s < 0) return false;
  if (s == 0) return true;
  if (path.environmentEnd && (s > 1 || t < 2)) return false;
  return !path.delta[static_cast<std::size_t>(t - 1)] && !path.delta[static_cast<std::size_t>(t)];
}

double strategyDensity(const PathDensities& path, int t) {
  if (!strategyPossible(path, t)) return 0;
  const int k = path.vertexCount() - 1;
  double p = 1;
  for (int i = 1; i < t; ++i)
    if (!path.delta[static_cast<std::size_t>(i - 1)]) p *= path.fromCamera[static_cast<std::size_t>(i)];
  for (int i = t; i <= k; ++i)
    if (i == k || !path.delta[static_cast<std::size_t>(i + 1)]) p *= path.fromLight[static_cast<std::size_t>(i)];
  return p;
}

float misWeight(const PathDensities& path, int t) {
  const double own = strategyDensity(path, t);
  if (!(own > 0)) return 0;
  double sum = 0;
  for (int other = 1; other <= path.vertexCount(); ++other) {
    const double ratio = strategyDensity(path, other) / own;
    sum += ratio * ratio;
  }
  return static_cast<float>(1 / sum);
}

}  // namespace pathfarm
