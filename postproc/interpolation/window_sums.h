#pragma once
// Sums of a per-pixel value over the square window of a given radius around every pixel
// (cut at the frame's edges), from a summed-area table: the checks that judge a pixel by its
// neighbourhood (radiance_check.h, caustic_check.h) read windows of any size in O(1).
#include <algorithm>
#include <cstddef>
#include <vector>

namespace pathfarm {

class WindowSums {
 public:
  WindowSums(const std::vector<double>& values, int width, int height)
      : width_(width), height_(height), table_(static_cast<size_t>(width + 1) * static_cast<size_t>(height + 1), 0.0) {
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x)
        at(x + 1, y + 1) = values[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)] +
                           at(x, y + 1) + at(x + 1, y) - at(x, y);
  }
  double around(int x, int y, int radius) const {
    const int x0 = std::max(0, x - radius), y0 = std::max(0, y - radius);
    const int x1 = std::min(width_, x + radius + 1), y1 = std::min(height_, y + radius + 1);
    return get(x1, y1) - get(x0, y1) - get(x1, y0) + get(x0, y0);
  }

 private:
  double& at(int x, int y) { return table_[static_cast<size_t>(y) * static_cast<size_t>(width_ + 1) + static_cast<size_t>(x)]; }
  double get(int x, int y) const {
    return table_[static_cast<size_t>(y) * static_cast<size_t>(width_ + 1) + static_cast<size_t>(x)];
  }
  int width_, height_;
  std::vector<double> table_;
};

}  // namespace pathfarm
