#include "renderer/metropolis/path_space/path_state.h"

namespace pathfarm {

PathSpaceState stateAt(const WindowScene& scene, CompletePath path, double tau) {
  PathSpaceState state;
  state.tau = tau;
  const std::optional<WindowInstant> instant = scene.time.instant(tau);
  if (instant) path.time = instant->shutterFraction;
  state.path = std::move(path);
  if (!instant) return state;
  const PathMeasurement m = measure(scene.frame(instant->frame), state.path);
  if (!m.raster || m.f.isBlack() || !m.f.isFinite()) return state;
  state.contribution = {instant->frame, *m.raster, m.f};
  state.density = state.contribution.scalar();
  return state;
}

}  // namespace pathfarm
