#include "renderer/gradient/temporal_correspondence.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>
#include <optional>

#include "renderer/decomposition/primary_motion.h"

namespace pathfarm {
namespace {

constexpr float kTolerance = 1.0f;  // pixels, forward-backward

struct Seen {
  std::optional<Vec2f> moved;  // the pixel centre carried to the other frame
  float depth = std::numeric_limits<float>::infinity();
};

// What the centre of every pixel of `geometry`'s frame sees at the shutter's opening,
// carried forward (towards the next frame) or backward.
std::vector<Seen> carried(const FrameGeometry& geometry, const Camera& camera, int width, int height, bool forward) {
  const Scene& scene = geometry.shot().scene();
  const PrimaryMotion motion(geometry, camera, geometry.frame());
  std::vector<Seen> seen(static_cast<size_t>(width) * static_cast<size_t>(height));
  tbb::parallel_for(0, height, [&](int y) {
    for (int x = 0; x < width; ++x) {
      const Vec2f centre{static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f};
      const Ray ray = camera.generateRay(centre, {0.5f, 0.5f}, scene.timeAt(geometry.frame(), 0));
      SurfaceHit hit;
      Seen& s = seen[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)];
      const bool found = geometry.intersect(ray, 0, hit);
      const MotionPair pair = found ? motion.ofSurface(hit, 0) : motion.ofBackground(ray.direction, 0);
      const std::optional<Vec2f>& m = forward ? pair.forward : pair.backward;
      if (m && std::isfinite(m->x) && std::isfinite(m->y)) s.moved = Vec2f{centre.x + m->x, centre.y + m->y};
      if (found) s.depth = hit.distance;
    }
  });
  return seen;
}

}  // namespace

std::vector<int32_t> temporalCorrespondence(const FrameGeometry& current, const FrameGeometry& next,
                                            const Camera& camera, int width, int height, bool followMotion) {
  const size_t pixels = static_cast<size_t>(width) * static_cast<size_t>(height);
  std::vector<int32_t> target(pixels, -1);
  if (!followMotion) {
    for (size_t p = 0; p < pixels; ++p) target[p] = static_cast<int32_t>(p);
    return target;
  }
  const std::vector<Seen> forward = carried(current, camera, width, height, true);
  const std::vector<Seen> backward = carried(next, camera, width, height, false);
  std::vector<int32_t> owner(pixels, -1);  // the source pixel holding each target
  for (size_t p = 0; p < pixels; ++p) {
    if (!forward[p].moved) continue;
    const float tx = std::floor(forward[p].moved->x), ty = std::floor(forward[p].moved->y);
    if (!(tx >= 0 && ty >= 0 && tx < static_cast<float>(width) && ty < static_cast<float>(height))) continue;
    const size_t q = static_cast<size_t>(ty) * static_cast<size_t>(width) + static_cast<size_t>(tx);
    const auto& back = backward[q].moved;
    const float cx = static_cast<float>(p % static_cast<size_t>(width)) + 0.5f;
    const float cy = static_cast<float>(p / static_cast<size_t>(width)) + 0.5f;
    if (!back || std::hypot(back->x - cx, back->y - cy) > kTolerance) continue;
    const int32_t holder = owner[q];
    if (holder >= 0 && forward[static_cast<size_t>(holder)].depth <= forward[p].depth) continue;
    if (holder >= 0) target[static_cast<size_t>(holder)] = -1;
    owner[q] = static_cast<int32_t>(p);
    target[p] = static_cast<int32_t>(q);
  }
  return target;
}

}  // namespace pathfarm
