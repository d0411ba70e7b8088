#include "renderer/decomposition/primary_motion.h"

namespace pathfarm {

std::optional<Vec2f> PrimaryMotion::difference(const std::optional<Vec2f>& from, const std::optional<Vec2f>& to) {
  if (!from || !to) return std::nullopt;
  return Vec2f{to->x - from->x, to->y - from->y};
}

std::optional<Vec2f> PrimaryMotion::ofSurface(int object, Vec3f position, float time, int offset) const {
  const Scene& scene = geometry_.shot().scene();
  const double now = scene.timeAt(frame_, time), then = scene.timeAt(frame_ + offset, time);
  Vec3f moved = position;
  if (geometry_.shot().shape(object).animated) {
    // Back to object space with the transform the point was traced with, forward with
    // the animation at the other time.
    const Vec3f local = geometry_.shapeToWorld(object, time).inversePoint(position);
    moved = scene.objects[static_cast<size_t>(object)].transform.transformAt(then).point(local);
  }
  return difference(camera_.project(position, now), camera_.project(moved, then));
}

std::optional<Vec2f> PrimaryMotion::ofBackground(Vec3f direction, float time, int offset) const {
  const Scene& scene = geometry_.shot().scene();
  return difference(camera_.projectDirection(direction, scene.timeAt(frame_, time)),
                    camera_.projectDirection(direction, scene.timeAt(frame_ + offset, time)));
}

}  // namespace pathfarm
