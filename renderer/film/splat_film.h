#pragma once
// A film that contributions land on from anywhere in the image (light tracing, Metropolis
// chains) while many threads render. Each pixel channel sums fixed-point integers with
// atomic adds: integer addition does not depend on its order, so the film's bits do not
// depend on the thread count, the tile size or how the work was split, as long as the
// same contributions are added.
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include "image/frame_image.h"
#include "renderer/math/vecmath.h"

namespace pathfarm {

class SplatFilm {
 public:
  // One unit of the fixed-point sums: values are rounded to multiples of this.
  static constexpr double kResolution = 0x1p-32;
  // A pixel's sum must stay below 2^31 (2^63 units). One splat is clamped to this and
  // counted, so that a single outlier cannot come near that bound.
  static constexpr double kLargestSplat = 0x1p20;

  SplatFilm(int width, int height);

  int width() const { return width_; }
  int height() const { return height_; }

  // Adds `value` to pixel (x, y). Thread-safe. Non-finite or negative channels are not
  // added and are counted as rejected; pixels outside the film are ignored.
  void add(int x, int y, Rgb value);
  // Adds every pixel of `other` (the same size) to this film, exactly.
  void add(const SplatFilm& other);

  // The pixel's sums times `scale`.
  Rgb value(int x, int y, double scale = 1) const;
  // R, G, B of every pixel times `scale`.
  FrameImage toImage(double scale = 1) const;

  uint64_t rejected() const { return rejected_.load(std::memory_order_relaxed); }
  uint64_t clamped() const { return clamped_.load(std::memory_order_relaxed); }

 private:
  size_t indexOf(int x, int y) const { return 3 * (static_cast<size_t>(y) * static_cast<size_t>(width_) + static_cast<size_t>(x)); }

  int width_, height_;
  std::unique_ptr<std::atomic<int64_t>[]> sums_;
  std::atomic<uint64_t> rejected_{0}, clamped_{0};
};

}  // namespace pathfarm
