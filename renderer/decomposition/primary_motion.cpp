#include "renderer/decomposition/primary_motion.h"

namespace pathfarm {

std::optional<Vec2f> PrimaryMotion::difference(const std::optional<Vec2f>& from, const std::optional<Vec2f>& to) {
  if (!from || !to) return std::nullopt;
  return Vec2f{to->x - from->x, to->y - from->y};
}

std::optional<Vec2f> PrimaryMotion::ofSurface(const SurfaceHit& hit, float time, int offset) const {
  const bool moves = geometry_.shot().shape(hit.object).animated;
  if (!moves && !camera_.isAnimated()) return Vec2f{0, 0};  // nothing moves: no need to project
  const Scene& scene = geometry_.shot().scene();
  const double now = scene.timeAt(frame_, time), then = scene.timeAt(frame_ + offset, time);
  // An animated object's shape is in object space: carry the point with the animation.
  const Vec3f moved = moves ? scene.objects[static_cast<size_t>(hit.object)].transform.transformAt(then).point(hit.shapePosition)
                            : hit.position;
  return difference(camera_.project(hit.position, now), camera_.project(moved, then));
}

std::optional<Vec2f> PrimaryMotion::ofBackground(Vec3f direction, float time, int offset) const {
  if (!camera_.isAnimated()) return Vec2f{0, 0};
  const Scene& scene = geometry_.shot().scene();
  return difference(camera_.projectDirection(direction, scene.timeAt(frame_, time)),
                    camera_.projectDirection(direction, scene.timeAt(frame_ + offset, time)));
}

}  // namespace pathfarm
