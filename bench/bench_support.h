#pragma once
// Shared by the benchmarks: timing a piece of work, and rendering a frame of a scene.
#include <chrono>
#include <memory>

#include "renderer/integrators/frame_renderer.h"

namespace pathfarm::bench {

template <class Work>
double seconds(Work work) {
  const auto start = std::chrono::steady_clock::now();
  work();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// A frame at the scene's max depth; with `decompose`, split by the default decomposition,
// its motion vectors reaching `motionSpan` frames.
// A reference passes a `firstSample` of its own, so that it shares no sample with the
// frames it measures.
inline FrameImage render(const Scene& scene, int width, int height, int spp, int64_t frame, bool decompose,
                         uint32_t firstSample = 0, MotionSpan motionSpan = {}) {
  RenderSettings settings;
  settings.motionSpan = motionSpan;
  settings.firstSample = firstSample;
  settings.width = width;
  settings.height = height;
  settings.spp = spp;
  settings.maxDepth = scene.defaults.maxDepth;
  if (decompose) settings.decomposition = std::make_shared<Decomposition>(Decomposition::standard());
  return FrameRenderer(scene, settings).render(frame);
}

}  // namespace pathfarm::bench
