#include "renderer/decomposition/specular_motion.h"

#include <algorithm>

namespace pathfarm {

SpecularMotion::SpecularMotion(const FrameGeometry& geometry, const std::vector<PreciseShape>& shapes,
                               const Decomposition& decomposition, int width, int height, MotionSpan span)
    : geometry_(geometry),
      nextGeometry_(geometry.shot(), geometry.frame() + span.forward),
      previousGeometry_(geometry.shot(), geometry.frame() - span.backward),
      automaton_(decomposition.automaton()),
      shapes_(shapes),
      camera_(geometry.shot().scene().camera, width, height),
      now_(geometry.shot().scene().timeAt(geometry.frame(), kShutterFraction)),
      next_(geometry.shot().scene().timeAt(geometry.frame() + span.forward, kShutterFraction)),
      previous_(geometry.shot().scene().timeAt(geometry.frame() - span.backward, kShutterFraction)),
      cameraNow_(camera_.at(now_)),
      sceneMoves_(camera_.isAnimated() || std::any_of(shapes.begin(), shapes.end(), [](const PreciseShape& s) {
                    return s.isAnimated() || s.deforms();
                  })) {
  for (int k = 0; k < decomposition.size(); ++k) specular_.push_back(decomposition.isSpecular(k));
}

SpecularTrack SpecularMotion::track(int x, int y, int component) const {
  SpecularTrack result;
  if (!isSpecular(component)) return result;
  const Vec2d film{x + 0.5, y + 0.5};
  const Ray ray{cameraNow_.position().toFloat(), normalize(cameraNow_.direction(film).toFloat())};
  auto chain = findSpecularChain(geometry_, automaton_, component, ray, kShutterFraction);
  if (!chain) return result;
  result.hasChain = true;
  if (!sceneMoves_) {  // every frame sees the same path
    result.forward = result.backward = Vec2d{0, 0};
    return result;
  }
  const auto deforms = [&](int object) { return shapes_[static_cast<size_t>(object)].deforms(); };
  result.walked = true;
  // The walk follows rigid motion only: a chain over a deforming surface gets no motion,
  // so its pixels are re-rendered rather than warped.
  if (deforms(chain->endpoint) || std::any_of(chain->links.begin(), chain->links.end(),
                                              [&](const ChainLink& link) { return deforms(link.object); }))
    return result;
  const auto moves = [&](int object) { return shapes_[static_cast<size_t>(object)].isAnimated(); };
  result.walked =
      camera_.isAnimated() || moves(chain->endpoint) ||
      std::any_of(chain->links.begin(), chain->links.end(), [&](const ChainLink& link) { return moves(link.object); });
  const ChainTracer tracer(shapes_, camera_, std::move(*chain));
  result.now = tracer.trace(film, now_);
  if (!result.now) return result;  // the float chain does not survive exact tracing
  const auto follow = [&](double seconds, const FrameGeometry& there, std::optional<ChainPath>& path,
                          std::optional<Vec2d>& motion) {
    if (result.walked) {
      path = walkInTime(tracer, *result.now, seconds, result.counts);
    } else {  // a chain at rest keeps its path, though another object may come in front of it
      path = result.now;
      path->seconds = seconds;
    }
    if (path && !isUnoccluded(*path, there, kShutterFraction)) path.reset();
    if (path) motion = Vec2d{path->film.x - film.x, path->film.y - film.y};
  };
  follow(next_, nextGeometry_, result.next, result.forward);
  follow(previous_, previousGeometry_, result.previous, result.backward);
  return result;
}

}  // namespace pathfarm
