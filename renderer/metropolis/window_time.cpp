#include "renderer/metropolis/window_time.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <sstream>

#include "renderer/scene/scene.h"

namespace pathfarm {
namespace {

// The largest double below `limit`: keeps rounded results inside half-open ranges.
double below(double value, double limit) { return value < limit ? value : std::nextafter(limit, -INFINITY); }

}  // namespace

WindowTime::WindowTime(FrameWindow window, float shutterOpen, float shutterClose)
    : window_(window), open_(shutterOpen), close_(shutterClose) {
  if (window.count < 1) throw std::invalid_argument("a frame window needs at least one frame");
  if (!(shutterOpen >= 0 && shutterClose <= 1 && shutterOpen <= shutterClose))
    throw std::invalid_argument("the shutter must open and close within a frame, opening first");
  if (shutterClose == shutterOpen) {
    std::ostringstream message;
    message << "the camera shutter has zero length (it opens and closes at " << shutterOpen
            << " of the frame): Metropolis light transport samples time over the open shutter, so there is "
               "nothing to sample; give the camera a shutter such as [0, 0.5]";
    throw std::invalid_argument(message.str());
  }
}

WindowTime WindowTime::of(const Scene& scene, FrameWindow window) {
  return WindowTime(window, scene.camera.shutterOpen, scene.camera.shutterClose);
}

bool WindowTime::isOpen(double tau) const {
  if (!contains(tau)) return false;
  const double fraction = tau - std::floor(tau);
  return fraction >= open_ && fraction < close_;
}

std::optional<WindowInstant> WindowTime::instant(double tau) const {
  if (!isOpen(tau)) return std::nullopt;
  const double frame = std::floor(tau);
  const double shutter = (tau - frame - open_) / (close_ - open_);
  return WindowInstant{static_cast<int64_t>(frame), std::min(static_cast<float>(shutter), 1.0f)};
}

double WindowTime::fromPrimary(double u) const {
  const double s = std::clamp(u, 0.0, 1.0) * window_.count;
  const double k = std::min(std::floor(s), static_cast<double>(window_.count - 1));
  const double frameStart = begin() + k;
  return below(frameStart + open_ + (s - k) * (close_ - open_), frameStart + close_);
}

double WindowTime::toPrimary(double tau) const {
  const double frame = std::floor(tau);
  const double fraction = (tau - frame - open_) / (close_ - open_);
  return below((frame - begin() + fraction) / window_.count, 1.0);
}

double WindowTime::openBefore(double x) const {
  const double y = x - begin();
  const double k = std::floor(y);
  return k * openPerFrame() + std::clamp(y - k - open_, 0.0, openPerFrame());
}

double WindowTime::atOpenMeasure(double m) const {
  const double perFrame = openPerFrame();
  const double k = std::min(std::floor(m / perFrame), static_cast<double>(window_.count - 1));
  const double r = std::clamp(m - k * perFrame, 0.0, perFrame);
  const double frameStart = begin() + k;
  return below(frameStart + open_ + r, frameStart + close_);
}

double WindowTime::atClosedMeasure(double m) const {
  const double perFrame = 1 - openPerFrame();
  if (perFrame <= 0) throw std::logic_error("an always-open shutter has no closed time");
  const double k = std::min(std::floor(m / perFrame), static_cast<double>(window_.count - 1));
  const double r = std::clamp(m - k * perFrame, 0.0, perFrame);
  const double frameStart = begin() + k;
  if (r < open_) return below(frameStart + r, frameStart + open_);
  return below(frameStart + close_ + (r - open_), frameStart + 1);
}

}  // namespace pathfarm
