#include "renderer/metropolis/window_geometry.h"

#include <stdexcept>
#include <string>

namespace pathfarm {

WindowGeometry::WindowGeometry(const ShotGeometry& shot, FrameWindow window) : window_(window) {
  if (window.count < 1) throw std::invalid_argument("a frame window needs at least one frame");
  frames_.reserve(static_cast<size_t>(window.count));
  for (int64_t f = window.first; f < window.end(); ++f) frames_.push_back(std::make_unique<const FrameGeometry>(shot, f));
}

const FrameGeometry& WindowGeometry::frame(int64_t frame) const {
  if (frame < window_.first || frame >= window_.end())
    throw std::out_of_range("frame " + std::to_string(frame) + " lies outside the window");
  return *frames_[static_cast<size_t>(frame - window_.first)];
}

}  // namespace pathfarm
