#pragma once
// Sums of a per-pixel value over the square window of a given radius around every pixel
// (cut at the frame's edges), from a summed-area table: the checks that count flagged
// pixels in a neighbourhood (solid_regions.h, flag_regions.h) read windows of any size in
// O(1), exactly, as the counts are whole numbers.
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

// Sums of a per-pixel value over the (2 radius + 1)^2 window around every pixel (cut at the
// frame's edges), columns first, then rows, each added in the same order wherever the
// frame starts. So a band of a frame's rows, given `radius` rows around it, has its rows'
// sums in the same bits as the whole frame (the filters' windows of rows), which a
// summed-area table's differences of large sums would not give for values that are not
// whole numbers. O(radius) per pixel.
inline std::vector<double> boxSums(const std::vector<double>& values, int width, int height, int radius) {
  std::vector<double> columns(values.size(), 0.0), sums(values.size(), 0.0);
  const auto at = [width](int x, int y) {
    return static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x);
  };
  for (int y = 0; y < height; ++y)
    for (int v = std::max(0, y - radius); v <= std::min(height - 1, y + radius); ++v)
      for (int x = 0; x < width; ++x) columns[at(x, y)] += values[at(x, v)];
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int u = std::max(0, x - radius); u <= std::min(width - 1, x + radius); ++u)
        sums[at(x, y)] += columns[at(u, y)];
  return sums;
}

}  // namespace pathfarm
