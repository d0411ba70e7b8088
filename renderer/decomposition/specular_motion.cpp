#include "renderer/decomposition/specular_motion.h"

#include <algorithm>

namespace pathfarm {

SpecularMotion::SpecularMotion(const FrameGeometry& geometry, const std::vector<PreciseShape>& shapes,
                               const Decomposition& decomposition, int width, int height)
    : geometry_(geometry),
      automaton_(decomposition.automaton()),
      shapes_(shapes),
      camera_(geometry.shot().scene().camera, width, height),
      now_(geometry.shot().scene().timeAt(geometry.frame(), kShutterFraction)),
      next_(geometry.shot().scene().timeAt(geometry.frame() + 1, kShutterFraction)),
      previous_(geometry.shot().scene().timeAt(geometry.frame() - 1, kShutterFraction)),
      cameraNow_(camera_.at(now_)) {
  const int eye = automaton_.next(automaton_.initial(), PathSymbol::E);
  for (int k = 0; k < decomposition.size(); ++k) {
    const bool named = k != decomposition.residual();
    specular_.push_back(named && automaton_.alive(eye, k) && !automaton_.alive(automaton_.next(eye, PathSymbol::D), k));
  }
}

SpecularTrack SpecularMotion::track(int x, int y, int component) const {
  SpecularTrack result;
  if (!isSpecular(component)) return result;
  const Vec2d film{x + 0.5, y + 0.5};
  const Ray ray{cameraNow_.position().toFloat(), normalize(cameraNow_.direction(film).toFloat())};
  auto chain = findSpecularChain(geometry_, automaton_, component, ray, kShutterFraction);
  if (!chain) return result;
  result.hasChain = true;
  const auto moves = [&](int object) { return shapes_[static_cast<size_t>(object)].isAnimated(); };
  const bool chainMoves =
      camera_.isAnimated() || moves(chain->endpoint) ||
      std::any_of(chain->links.begin(), chain->links.end(), [&](const ChainLink& link) { return moves(link.object); });
  if (!chainMoves) {  // nothing to walk: every frame sees the same path
    result.forward = result.backward = Vec2d{0, 0};
    return result;
  }
  result.walked = true;
  const ChainTracer tracer(shapes_, camera_, std::move(*chain));
  result.now = tracer.trace(film, now_);
  if (!result.now) return result;  // the float chain does not survive exact tracing
  const auto walk = [&](double seconds, std::optional<ChainPath>& path, std::optional<Vec2d>& motion) {
    path = walkInTime(tracer, *result.now, seconds, result.counts);
    if (path) motion = Vec2d{path->film.x - film.x, path->film.y - film.y};
  };
  walk(next_, result.next, result.forward);
  walk(previous_, result.previous, result.backward);
  return result;
}

}  // namespace pathfarm
