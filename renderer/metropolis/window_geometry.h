#pragma once
// The placed geometry of every frame of a window, built once before the chains start and
// then only read, so every thread shares it. A path at window time tau is traced in the
// FrameGeometry of frame floor(tau) at that frame's shutter fraction.
#include <memory>
#include <vector>

#include "renderer/accel/frame_geometry.h"
#include "renderer/metropolis/window_time.h"

namespace pathfarm {

class WindowGeometry {
 public:
  WindowGeometry(const ShotGeometry& shot, FrameWindow window);

  const FrameWindow& window() const { return window_; }
  // Throws std::out_of_range for a frame outside the window.
  const FrameGeometry& frame(int64_t frame) const;

 private:
  FrameWindow window_;
  std::vector<std::unique_ptr<const FrameGeometry>> frames_;
};

}  // namespace pathfarm
