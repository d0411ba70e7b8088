#include "renderer/decomposition/primary_motion.h"

namespace pathfarm {
namespace {

std::optional<Vec2f> difference(const std::optional<Vec2f>& from, const std::optional<Vec2f>& to) {
  if (!from || !to) return std::nullopt;
  return Vec2f{to->x - from->x, to->y - from->y};
}

const MotionPair kStill{Vec2f{0, 0}, Vec2f{0, 0}};

}  // namespace

MotionPair PrimaryMotion::ofSurface(const SurfaceHit& hit, float time) const {
  return ofSurface(hit, time, camera_.cameraToWorld(geometry_.shot().scene().timeAt(frame_, time)));
}

MotionPair PrimaryMotion::ofBackground(Vec3f direction, float time) const {
  return ofBackground(direction, time, camera_.cameraToWorld(geometry_.shot().scene().timeAt(frame_, time)));
}

MotionPair PrimaryMotion::ofSurface(const SurfaceHit& hit, float time, const Transform& cameraNow) const {
  const PreparedShape& shape = geometry_.shot().shape(hit.object);
  const bool moves = shape.animated || shape.deforming;
  if (!moves && !camera_.isAnimated()) return kStill;  // nothing moves: no need to project
  const Scene& scene = geometry_.shot().scene();
  const auto imageAt = [&](int offset) {
    const double seconds = scene.timeAt(frame_ + offset, time);
    const Vec3f point = offset != 0 && moves ? geometry_.shot().surfacePointAt(hit, seconds) : hit.position;
    return camera_.project(point, seconds);
  };
  const auto now = camera_.project(hit.position, cameraNow);
  return {difference(now, imageAt(span_.forward)), difference(now, imageAt(-span_.backward))};
}

MotionPair PrimaryMotion::ofBackground(Vec3f direction, float time, const Transform& cameraNow) const {
  if (!camera_.isAnimated()) return kStill;
  const Scene& scene = geometry_.shot().scene();
  const auto imageAt = [&](int offset) {
    return camera_.projectDirection(direction, scene.timeAt(frame_ + offset, time));
  };
  const auto now = camera_.projectDirection(direction, cameraNow);
  return {difference(now, imageAt(span_.forward)), difference(now, imageAt(-span_.backward))};
}

}  // namespace pathfarm
