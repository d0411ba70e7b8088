#include "renderer/bidirectional/pssmlt_strategy.h"

#include <algorithm>

#include "renderer/bidirectional/connection.h"
#include "renderer/bidirectional/subpath.h"

namespace pathfarm {

StrategyEvaluation evaluateStrategy(const BdptScene& bdpt, float time, int depth, PrimarySampleStreams streams,
                                    Subpath& cameraScratch, Subpath& lightScratch) {
  StrategyEvaluation result;
  const int strategies = depth + 2;
  result.s = std::min(static_cast<int>(streams.connection.next1D() * static_cast<float>(strategies)), strategies - 1);
  result.t = strategies - result.s;
  const Vec2f u = streams.camera.next2D();
  result.raster = {u.x * static_cast<float>(bdpt.camera.width()), u.y * static_cast<float>(bdpt.camera.height())};
  const Vec2f lens = streams.camera.next2D();
  if (generateCameraSubpath(bdpt, time, result.raster, lens, streams.camera, result.t, cameraScratch) != result.t)
    return result;
  if (generateLightSubpath(bdpt, time, streams.light, result.s, lightScratch) != result.s) return result;
  const auto sample =
      connectStrategy(bdpt, time, cameraScratch, lightScratch, result.s, result.t, streams.connection);
  if (!sample) return result;
  if (sample->lightTracing) result.raster = sample->raster;
  result.contribution = sample->contribution * static_cast<float>(strategies);
  return result;
}

}  // namespace pathfarm
