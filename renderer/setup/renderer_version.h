#pragma once
// Which renderer made a frame's pixels. Bump it with any change that alters a pixel of
// FrameRenderer's plain path tracing (every reference is one) for the same scene and
// settings (bench/same_frames.sh tells): cached references (client/reference_cache.h) are
// keyed by it, so a bump renders them anew. Other integrators' changes leave it alone.
namespace pathfarm {

// 2: rough metals compensated for multiple scattering (materials/multiple_scattering.h).
// 3: rough glass and glTF's thin-walled transmission compensated too.
// 4: camera samples at the centres of 1024 shutter buckets (integrators/shutter_buckets.h).
inline constexpr int kRendererVersion = 4;

}  // namespace pathfarm
