#pragma once
// Which renderer made a frame's pixels. Bump it with any change that alters a pixel an
// integrator produces for the same scene and settings (bench/same_frames.sh tells): cached
// references (client/reference_cache.h) are keyed by it, so a bump renders them anew.
namespace pathfarm {

inline constexpr int kRendererVersion = 1;

}  // namespace pathfarm
