#pragma once
// Renders frames for gradient-domain reconstruction (docs/gradient-domain.md): the primal
// image, horizontal and vertical differences with their variances and the directly seen
// emission (GPT, Kettunen et al. 2015), and with `temporal` also the temporal offset
// frame (TGPT, Manzi et al. 2016): every base sample of frame f is replayed with the same
// primary-sample-space random numbers at the time of frame f + 1, through the pixel its
// correspondence names, and the difference of the two is the temporal difference.
// Tiles render in parallel; each pixel's samples are accumulated in a fixed order and
// neighbours are combined only afterwards, from the pixels' estimates
// (gradient_estimates.h), so the bits do not depend on thread count or tile size, and a
// frame rendered in windows and joined is the frame rendered whole.
#include <memory>
#include <mutex>

#include <tbb/task_arena.h>

#include "renderer/integrators/frame_integrator.h"

namespace pathfarm {

// The fewest samples with mixed offsets GradientSettings::mixedEvery leaves a pixel.
inline constexpr int kMinMixedSamples = 8;

struct GradientSettings {
  bool temporal = false;      // also the temporal offset frame towards the next frame
  bool motionVectors = true;  // temporal offsets follow the primary motion
  int batches = 1;            // 1: uniform sampling; more: adaptive after the first batch
  // The temporal offset traces its own spatial offsets (for the mixed differences) on one
  // sample of every `mixedEvery` of a pixel (sample indices 0, N, 2N, ...); the others
  // replay the base path alone. The mixed differences then rest on fewer samples, and
  // each skipped sample saves about half of the temporal offset's rays. N is lowered to
  // leave a pixel of the first batch kMinMixedSamples of them: a variance from one or two
  // samples would give a noisy row full weight. 4 costs about 0.9 of N = 1 at equal error
  // (docs/gradient-domain.md).
  int mixedEvery = 4;
};

class GradientFrameRenderer : public FrameIntegrator {
 public:
  GradientFrameRenderer(const Scene& scene, RenderSettings settings, GradientSettings gradient);
  ~GradientFrameRenderer() override;

  FrameImage render(int64_t frame, const ProgressCallback& progress = {}, RenderStats* stats = nullptr) const override;
  // The estimates (gradient_estimates.h) of a window's pixels; gradientFrameFromEstimates
  // joins the windows of a frame. Uniform sampling only (one batch): adaptive batches
  // spread samples over the whole frame, so a smaller window is std::invalid_argument,
  // as is one outside the frame. The frame's placement and correspondence are kept
  // between calls for the same frame, so its windows pay for them once.
  FrameImage renderWindow(int64_t frame, const PixelWindow& window, const ProgressCallback& progress = {},
                          RenderStats* stats = nullptr) const;

 private:
  struct Shot;
  struct FrameSetup;
  std::shared_ptr<const FrameSetup> setupFor(int64_t frame, tbb::task_arena& arena) const;
  // mixedEvery, lowered to leave kMinMixedSamples per pixel of the first batch.
  int effectiveMixedEvery() const;
  FrameImage estimate(int64_t frame, const PixelWindow& window, const ProgressCallback& progress,
                      RenderStats* stats) const;

  const Scene& scene_;
  RenderSettings settings_;
  GradientSettings gradient_;
  std::unique_ptr<Shot> shot_;
  mutable std::mutex setupMutex_;
  mutable std::shared_ptr<const FrameSetup> lastSetup_;
};

}  // namespace pathfarm
