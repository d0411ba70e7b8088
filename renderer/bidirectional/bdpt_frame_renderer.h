#pragma once
// Renders frames by bidirectional path tracing (`pathfarm render --integrator bdpt`).
// Each pixel sample is the path tracer's: the pixel position and shutter time stratified
// over the pixel's samples (StratifiedPixel), then a SampleStream keyed by (scene
// seed, frame, pixel, sample index) giving the lens, a camera subpath, a light subpath
// and their connections.
// Camera strategies (t >= 2) are averaged per pixel in a fixed order; light tracing
// (t = 1) lands anywhere and is splatted into a SplatFilm, whose sums do not depend on
// their order, so the frame is the same bits for any thread count and tile size.
//
// Output: R, G, B (the beauty), and variance.R/G/B: the variance of the pixel's mean of
// its camera strategies only (light-tracing splats come from other pixels' samples and
// are not in it), so it is a lower bound on the beauty's variance.
#include "image/frame_image.h"
#include "renderer/integrators/frame_integrator.h"

namespace pathfarm {

class BdptFrameRenderer : public FrameIntegrator {
 public:
  // Throws std::invalid_argument for settings bidirectional tracing does not support
  // (a decomposition).
  BdptFrameRenderer(const Scene& scene, RenderSettings settings);
  ~BdptFrameRenderer() override;

  FrameImage render(int64_t frame, const ProgressCallback& progress = {}, RenderStats* stats = nullptr) const override;

 private:
  struct Shot;
  const Scene& scene_;
  RenderSettings settings_;
  std::unique_ptr<Shot> shot_;
};

}  // namespace pathfarm
