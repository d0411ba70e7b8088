#pragma once
// The ray rate Embree alone reaches on a frame's geometry: the ceiling the path tracer's
// own ray rate is measured against.
#include <embree3/rtcore.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <cstdint>

#include "renderer/accel/frame_geometry.h"
#include "renderer/math/sampling.h"
#include "renderer/sampling/sample_stream.h"

namespace pathfarm::bench {

// Traces `count` random rays (origins inside the geometry's bounds, uniform directions)
// with rtcIntersect1 in parallel; returns rays per second.
inline double embreeRaysPerSecond(const FrameGeometry& geometry, uint64_t count) {
  const Bounds3 b = geometry.bounds();
  const auto start = std::chrono::steady_clock::now();
  tbb::parallel_for(tbb::blocked_range<uint64_t>(0, count, 4096), [&](const tbb::blocked_range<uint64_t>& r) {
    SampleStream stream({7, 0, static_cast<int32_t>(r.begin() >> 12), 0, 0});
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (uint64_t i = r.begin(); i != r.end(); ++i) {
      const Vec3f u{stream.next1D(), stream.next1D(), stream.next1D()};
      const Vec3f d = sampleUniformSphere(stream.next2D());
      RTCRayHit rh{};
      rh.ray.org_x = b.lower.x + u.x * (b.upper.x - b.lower.x);
      rh.ray.org_y = b.lower.y + u.y * (b.upper.y - b.lower.y);
      rh.ray.org_z = b.lower.z + u.z * (b.upper.z - b.lower.z);
      rh.ray.dir_x = d.x;
      rh.ray.dir_y = d.y;
      rh.ray.dir_z = d.z;
      rh.ray.tfar = 1e30f;
      rh.ray.time = stream.next1D();
      rh.ray.mask = 0xffffffffu;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(geometry.embreeScene(), &context, &rh);
    }
  });
  return static_cast<double>(count) / std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace pathfarm::bench
