#include "renderer/decomposition/primary_motion.h"

namespace pathfarm {
namespace {

std::optional<Vec2f> difference(const std::optional<Vec2f>& from, const std::optional<Vec2f>& to) {
  if (!from || !to) return std::nullopt;
  return Vec2f{to->x - from->x, to->y - from->y};
}

const MotionPair kStill{Vec2f{0, 0}, Vec2f{0, 0}};

}  // namespace

Transform PrimaryMotion::cameraAt(float time, int offset) const {
  return camera_.cameraToWorld(geometry_.shot().scene().timeAt(frame_ + offset, time));
}

MotionPair PrimaryMotion::ofSurface(const SurfaceHit& hit, float time) const {
  const Transform now = cameraAt(time, 0), forward = cameraAt(time, span_.forward),
                  backward = cameraAt(time, -span_.backward);
  return ofSurface(hit, time, {now, forward, backward});
}

MotionPair PrimaryMotion::ofBackground(Vec3f direction, float time) const {
  const Transform now = cameraAt(time, 0), forward = cameraAt(time, span_.forward),
                  backward = cameraAt(time, -span_.backward);
  return ofBackground(direction, {now, forward, backward});
}

MotionPair PrimaryMotion::ofSurface(const SurfaceHit& hit, float time, const CameraPlacements& camera) const {
  const PreparedShape& shape = geometry_.shot().shape(hit.object);
  const bool moves = shape.animated || shape.deforming;
  if (!moves && !camera_.isAnimated()) return kStill;  // nothing moves: no need to project
  const Scene& scene = geometry_.shot().scene();
  const auto imageAt = [&](int offset, const Transform& placement) {
    const double seconds = scene.timeAt(frame_ + offset, time);
    const Vec3f point = offset != 0 && moves ? geometry_.shot().surfacePointAt(hit, seconds) : hit.position;
    return camera_.project(point, placement);
  };
  const auto now = camera_.project(hit.position, camera.now);
  return {difference(now, imageAt(span_.forward, camera.forward)),
          difference(now, imageAt(-span_.backward, camera.backward))};
}

MotionPair PrimaryMotion::ofBackground(Vec3f direction, const CameraPlacements& camera) const {
  if (!camera_.isAnimated()) return kStill;
  const auto now = camera_.projectDirection(direction, camera.now);
  return {difference(now, camera_.projectDirection(direction, camera.forward)),
          difference(now, camera_.projectDirection(direction, camera.backward))};
}

}  // namespace pathfarm
