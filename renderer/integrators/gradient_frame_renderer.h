#pragma once
// Renders frames for gradient-domain reconstruction (docs/gradient-domain.md): the primal
// image, horizontal and vertical differences with their variances and the directly seen
// emission (GPT, Kettunen et al. 2015), and with `temporal` also the temporal offset
// frame (TGPT, Manzi et al. 2016): every base sample of frame f is replayed with the same
// primary-sample-space random numbers at the time of frame f + 1, through the pixel its
// correspondence names, and the difference of the two is the temporal difference.
// Tiles render in parallel; each pixel's samples are accumulated in a fixed order and
// neighbours are combined only afterwards, so the bits do not depend on thread count or
// tile size. Frames are rendered whole: differences need both pixels of a pair.
#include <memory>

#include "renderer/integrators/frame_integrator.h"

namespace pathfarm {

struct GradientSettings {
  bool temporal = false;      // also the temporal offset frame towards the next frame
  bool motionVectors = true;  // temporal offsets follow the primary motion
  int batches = 1;            // 1: uniform sampling; more: adaptive after the first batch
  // The temporal offset traces its own spatial offsets (for the mixed differences) on one
  // sample of every `mixedEvery` of a pixel (sample indices 0, N, 2N, ...); the others
  // replay the base path alone. The mixed differences then rest on fewer samples, and
  // each skipped sample saves about half of the temporal offset's rays.
  int mixedEvery = 1;
};

class GradientFrameRenderer : public FrameIntegrator {
 public:
  GradientFrameRenderer(const Scene& scene, RenderSettings settings, GradientSettings gradient);
  ~GradientFrameRenderer() override;

  FrameImage render(int64_t frame, const ProgressCallback& progress = {}, RenderStats* stats = nullptr) const override;

 private:
  struct Shot;
  const Scene& scene_;
  RenderSettings settings_;
  GradientSettings gradient_;
  std::unique_ptr<Shot> shot_;
};

}  // namespace pathfarm
