#include "renderer/film/splat_film.h"

#include <cmath>
#include <stdexcept>

namespace pathfarm {

SplatFilm::SplatFilm(int width, int height)
    : width_(width), height_(height),
      sums_(new std::atomic<int64_t>[3 * static_cast<size_t>(std::max(width, 0)) * static_cast<size_t>(std::max(height, 0))]()) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("a splat film needs a positive size");
}

void SplatFilm::add(int x, int y, Rgb value) {
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
  if (!value.isFinite() || value.r < 0 || value.g < 0 || value.b < 0) {
    rejected_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  const size_t i = indexOf(x, y);
  for (int c = 0; c < 3; ++c) {
    double v = value[c];
    if (v > kLargestSplat) {
      v = kLargestSplat;
      clamped_.fetch_add(1, std::memory_order_relaxed);
    }
    const auto units = static_cast<int64_t>(std::llround(v / kResolution));
    if (units != 0) sums_[i + static_cast<size_t>(c)].fetch_add(units, std::memory_order_relaxed);
  }
}

void SplatFilm::add(const SplatFilm& other) {
  if (other.width_ != width_ || other.height_ != height_) throw std::invalid_argument("splat films of different sizes");
  const size_t n = 3 * static_cast<size_t>(width_) * static_cast<size_t>(height_);
  for (size_t i = 0; i < n; ++i) sums_[i].fetch_add(other.sums_[i].load(std::memory_order_relaxed), std::memory_order_relaxed);
  rejected_.fetch_add(other.rejected(), std::memory_order_relaxed);
  clamped_.fetch_add(other.clamped(), std::memory_order_relaxed);
}

Rgb SplatFilm::value(int x, int y, double scale) const {
  const size_t i = indexOf(x, y);
  const auto channel = [&](size_t c) {
    return static_cast<float>(static_cast<double>(sums_[i + c].load(std::memory_order_relaxed)) * kResolution * scale);
  };
  return {channel(0), channel(1), channel(2)};
}

FrameImage SplatFilm::toImage(double scale) const {
  FrameImage image(width_, height_);
  std::vector<float>* planes[3] = {&image.addChannel("R"), &image.addChannel("G"), &image.addChannel("B")};
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) {
      const Rgb v = value(x, y, scale);
      const size_t p = static_cast<size_t>(y) * static_cast<size_t>(width_) + static_cast<size_t>(x);
      for (int c = 0; c < 3; ++c) (*planes[c])[p] = v[c];
    }
  return image;
}

}  // namespace pathfarm
