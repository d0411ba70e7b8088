#include "renderer/integrators/shutter_buckets.h"

#include <algorithm>

namespace pathfarm {

ShutterBuckets::ShutterBuckets(const Scene& scene, const Camera& camera, int64_t frame) {
  placements_.reserve(kBuckets);
  for (int b = 0; b < kBuckets; ++b)
    placements_.push_back(camera.cameraToWorld(scene.timeAt(frame, time((static_cast<float>(b) + 0.5f) / kBuckets))));
}

int ShutterBuckets::bucketOf(float u) {
  return std::clamp(static_cast<int>(u * static_cast<float>(kBuckets)), 0, kBuckets - 1);
}

float ShutterBuckets::time(float u) { return (static_cast<float>(bucketOf(u)) + 0.5f) / static_cast<float>(kBuckets); }

}  // namespace pathfarm
