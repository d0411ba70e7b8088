#pragma once
// Renders frames of a scene: builds the shot's geometry once, then per frame places the
// animated objects, splits the image into tiles and renders them in parallel with TBB.
// Each pixel's samples are independent streams (sample_stream.h) accumulated in a
// fixed order, so the result is the same bits for any thread count and tile size.
#include <cstdint>
#include <memory>
#include <mutex>

#include "renderer/integrators/frame_integrator.h"

namespace pathfarm {

class FrameRenderer : public FrameIntegrator {
 public:
  FrameRenderer(const Scene& scene, RenderSettings settings);
  // The same shot with other settings (samples, decomposition, resolution): shares the
  // built geometry, so it costs next to nothing.
  FrameRenderer(const FrameRenderer& shot, RenderSettings settings);
  ~FrameRenderer() override;

  // The frame's beauty in R, G, B and the variance of each pixel's mean in variance.R/G/B,
  // and with a decomposition its components' buffers (decomposed_film.h).
  FrameImage render(int64_t frame, const ProgressCallback& progress = {}, RenderStats* stats = nullptr) const override;
  // Only a part of the frame (a farm tile): the image has the window's size and its pixels
  // are bit-identical to the same pixels of render(). Throws std::invalid_argument for a
  // window outside the frame. With `only` (a byte per window pixel, row-major), pixels whose
  // byte is 0 are not rendered and stay 0 in every channel.
  FrameImage renderWindow(int64_t frame, const PixelWindow& window, const ProgressCallback& progress = {},
                          RenderStats* stats = nullptr, const std::vector<uint8_t>* only = nullptr) const;

  const Scene& scene() const { return scene_; }
  const RenderSettings& settings() const { return settings_; }

 private:
  struct Shot;
  // The placed geometry of `frame`, built once and shared by the calls rendering windows
  // of the same frame (a farm worker renders many tiles of one frame in a row).
  std::shared_ptr<const FrameGeometry> geometryFor(int64_t frame) const;

  const Scene& scene_;
  RenderSettings settings_;
  std::shared_ptr<Shot> shot_;
  mutable std::mutex geometryMutex_;
  mutable std::shared_ptr<const FrameGeometry> lastGeometry_;
};

}  // namespace pathfarm
