#include "postproc/interpolation/flag_regions.h"

#include <utility>

#include "postproc/interpolation/window_sums.h"

namespace pathfarm {

std::vector<uint8_t> dilated(const std::vector<uint8_t>& mask, int width, int height, int radius) {
  const WindowSums flagged(std::vector<double>(mask.begin(), mask.end()), width, height);
  return pixelsWhere(width, height, [&](int x, int y) { return flagged.around(x, y, radius) > 0; });
}

std::vector<uint8_t> grownRegions(std::vector<uint8_t> strong, const std::vector<uint8_t>& weak, int width,
                                  int height, int reach) {
  std::vector<size_t> front;
  for (size_t p = 0; p < strong.size(); ++p)
    if (strong[p]) front.push_back(p);
  for (int step = 0; step < reach && !front.empty(); ++step) {
    std::vector<size_t> next;
    for (const size_t p : front) {
      const int x = static_cast<int>(p % static_cast<size_t>(width)), y = static_cast<int>(p / static_cast<size_t>(width));
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
          const size_t q = static_cast<size_t>(ny) * static_cast<size_t>(width) + static_cast<size_t>(nx);
          if (weak[q] && !strong[q]) {
            strong[q] = 1;
            next.push_back(q);
          }
        }
    }
    front = std::move(next);
  }
  return strong;
}

}  // namespace pathfarm
