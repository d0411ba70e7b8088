#pragma once
// What every integrator that renders whole frames is (`pathfarm render --integrator`, the
// farm's render tasks): a FrameIntegrator, built for a scene and its settings, renders a
// frame by number. The vocabulary they share is here too: the settings of a render, its
// counts, and progress. Integrators are chosen by name in renderer/setup/integrator_factory.h.
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>

#include "image/frame_image.h"
#include "renderer/decomposition/decomposition.h"
#include "renderer/decomposition/primary_motion.h"
#include "renderer/integrators/path_tracer.h"
#include "renderer/scene/scene.h"

namespace pathfarm {

// Pixels [x0, x1) x [y0, y1) of a frame.
struct PixelWindow {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;

  int width() const { return x1 - x0; }
  int height() const { return y1 - y0; }
};

// Where the sample indices of a reference start: far above any shot's spp (at most 2^20),
// so a reference and the renders it measures draw disjoint, independent samples.
inline constexpr uint32_t kIndependentFirstSample = 1u << 31;

struct RenderSettings {
  int width = 320, height = 240;
  int spp = 16;
  int maxDepth = 8;
  int tileSize = 32;
  int threads = 0;  // 0: every core
  // Split every pixel into these path-space components (null: beauty only).
  std::shared_ptr<const Decomposition> decomposition;
  // How far the components' motion vectors reach (a keyframe's: its neighbouring keyframes).
  MotionSpan motionSpan;
  // With a decomposition: measure the motion (the components', the frame's, its
  // silhouettes). A render whose motion nobody reads skips it, for it costs per pixel:
  // primary motion on 8 samples and the specular components' manifold walks, as much as
  // several of a 4-spp render's paths. Without it those channels are zero.
  bool motion = true;
  // Sample indices run from here (sample_stream.h). A render that measures another must
  // share none of its samples: a reference starts at kIndependentFirstSample.
  uint32_t firstSample = 0;
  // With a decomposition: the components' reflectance takes this many samples a pixel (0 or
  // at most spp: spp). The first spp are the render's paths; the rest trace the camera ray
  // only to its first non-specular vertex, which costs a small part of a path and sharpens
  // the texture edges an in-between frame's interpolation modulates (frame_interpolation.h).
  int reflectanceSpp = 0;

  static RenderSettings defaultsOf(const Scene& scene);
};

struct RenderStats {
  uint64_t samples = 0;
  uint64_t nonFiniteSamples = 0;  // dropped, never written
  RayCounts rays;
  double seconds = 0;
};

// One thread's counts during a render; renders keep one per thread and add them up.
struct SampleCounters {
  uint64_t samples = 0, nonFinite = 0;
  RayCounts rays;
};

// The totals of `perThread` (any range of SampleCounters) for a render begun at `start`.
template <class PerThread>
RenderStats totalOf(const PerThread& perThread, std::chrono::steady_clock::time_point start) {
  RenderStats total;
  for (const SampleCounters& c : perThread) {
    total.samples += c.samples;
    total.nonFiniteSamples += c.nonFinite;
    total.rays.closestHit += c.rays.closestHit;
    total.rays.shadow += c.rays.shadow;
  }
  total.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return total;
}

// The header every rendered frame carries: scene, frame, spp, max depth, seed and the
// number of non-finite samples dropped.
void writeRenderAttributes(FrameImage& image, const Scene& scene, int64_t frame, const RenderSettings& settings,
                           const RenderStats& stats);

// Called from worker threads as tiles finish: (tiles done, tiles in all).
using ProgressCallback = std::function<void(size_t, size_t)>;

class FrameIntegrator {
 public:
  virtual ~FrameIntegrator() = default;
  // The frame's image: at least the beauty in R, G, B; what else depends on the integrator.
  virtual FrameImage render(int64_t frame, const ProgressCallback& progress = {},
                            RenderStats* stats = nullptr) const = 0;
};

}  // namespace pathfarm
