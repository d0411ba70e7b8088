#include "renderer/integrators/shift_mapping.h"

#include <cmath>

namespace pathfarm {

bool isConnectable(const Bsdf& bsdf) {
  const LobeList lobes = bsdf.lobes();
  if (lobes.count == 0) return false;
  for (int i = 0; i < lobes.count; ++i)
    if (lobes.lobes[i].delta || lobes.lobes[i].symbol != LobeSymbol::D) return false;
  return true;
}

std::optional<Reconnection> reconnect(Vec3f from, Vec3f baseFrom, const SurfaceHit& target) {
  const Vec3f toTarget = target.position - from, baseToTarget = target.position - baseFrom;
  const float d2 = dot(toTarget, toTarget), baseD2 = dot(baseToTarget, baseToTarget);
  if (!(d2 > 0) || !(baseD2 > 0)) return std::nullopt;
  const float distance = std::sqrt(d2);
  const Vec3f direction = toTarget / distance;
  const float cosine = dot(direction, target.geometricNormal);
  const float baseCosine = dot(baseToTarget, target.geometricNormal) / std::sqrt(baseD2);
  if (cosine * baseCosine <= 0) return std::nullopt;
  const float jacobian = (std::abs(cosine) / d2) / (std::abs(baseCosine) / baseD2);
  if (!std::isfinite(jacobian)) return std::nullopt;
  return Reconnection{direction, distance, jacobian};
}

}  // namespace pathfarm
