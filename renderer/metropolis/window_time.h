#pragma once
// Time across a window of frames, the domain temporal Metropolis chains move in
// (Van de Woestijne et al. 2017): a continuous coordinate tau, in frames, over
// [first, first + count). Frame floor(tau) owns tau; the shutter is open for the
// fractions [shutterOpen, shutterClose) of each frame, and a path at a time when the
// shutter is closed contributes nothing.
#include <cstdint>
#include <optional>

namespace pathfarm {

struct Scene;

// Frames [first, first + count).
struct FrameWindow {
  int64_t first = 0;
  int count = 1;

  int64_t end() const { return first + count; }
};

// A point of open shutter time: the frame and the shutter fraction in [0, 1], which is
// the ray time of that frame's FrameGeometry.
struct WindowInstant {
  int64_t frame = 0;
  float shutterFraction = 0;
};

class WindowTime {
 public:
  // Throws std::invalid_argument for an empty window or a shutter of zero length (no
  // time at which light reaches the film, so nothing to sample).
  WindowTime(FrameWindow window, float shutterOpen, float shutterClose);
  // The window with the scene camera's shutter.
  static WindowTime of(const Scene& scene, FrameWindow window);

  const FrameWindow& window() const { return window_; }
  double begin() const { return static_cast<double>(window_.first); }
  double end() const { return static_cast<double>(window_.end()); }
  // Open time per frame and in the whole window, in frames.
  double openPerFrame() const { return close_ - open_; }
  double openLength() const { return openPerFrame() * window_.count; }
  bool alwaysOpen() const { return open_ == 0 && close_ == 1; }

  bool contains(double tau) const { return tau >= begin() && tau < end(); }
  // Whether tau lies in the window and the shutter is open then.
  bool isOpen(double tau) const;
  // The frame and ray time of tau; nothing when the shutter is closed or tau lies outside.
  std::optional<WindowInstant> instant(double tau) const;

  // A primary sample u in [0, 1) mapped uniformly over the window's open time, and back.
  double fromPrimary(double u) const;
  double toPrimary(double tau) const;

  // Open time in [begin(), x) for x in the window (the cumulative measure used to sample
  // uniformly over the open or the closed parts of an interval), and its inverses.
  double openBefore(double x) const;
  double closedBefore(double x) const { return (x - begin()) - openBefore(x); }
  double atOpenMeasure(double m) const;
  double atClosedMeasure(double m) const;

 private:
  FrameWindow window_;
  double open_, close_;
};

}  // namespace pathfarm
