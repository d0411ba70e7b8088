#include "scheduler/http/thumbnails.h"

#include <algorithm>

#include "image/exr_io.h"
#include "image/png_preview.h"

namespace pathfarm::farm {

FrameImage shrinkBeauty(const std::filesystem::path& file, const std::string& label, int maxEdge) {
  // Block sums, filled a strip at a time: a large frame is never whole in memory.
  constexpr const char* kBeauty[3] = {"R", "G", "B"};
  FrameImage small;
  std::vector<double> sums[3];
  int factor = 1;
  const auto [width, height] = readExrStrips(file, label, {kBeauty, kBeauty + 3}, 16, [&](const ExrStrip& strip) {
    if (strip.firstRow == 0) {
      factor = std::max(1, (std::max(strip.width, strip.height) + maxEdge - 1) / maxEdge);
      small = FrameImage((strip.width + factor - 1) / factor, (strip.height + factor - 1) / factor);
      for (std::vector<double>& sum : sums) sum.assign(small.pixelCount(), 0.0);
    }
    for (int c = 0; c < 3; ++c)
      for (int row = 0; row < strip.rows; ++row) {
        const float* line = strip.planes[static_cast<size_t>(c)] + static_cast<ptrdiff_t>(row) * strip.width;
        double* target = sums[c].data() + static_cast<ptrdiff_t>((strip.firstRow + row) / factor) * small.width();
        for (int x = 0; x < strip.width; ++x) target[x / factor] += line[x];
      }
    return true;
  });
  // Each pixel is the mean of its block, fewer pixels at the right and bottom edges.
  for (int c = 0; c < 3; ++c) {
    std::vector<float>& out = small.addChannel(kBeauty[c]);
    for (int y = 0; y < small.height(); ++y)
      for (int x = 0; x < small.width(); ++x) {
        const int count = (std::min(width, (x + 1) * factor) - x * factor) * (std::min(height, (y + 1) * factor) - y * factor);
        const size_t p = static_cast<size_t>(y) * static_cast<size_t>(small.width()) + static_cast<size_t>(x);
        out[p] = static_cast<float>(sums[c][p] / count);
      }
  }
  return small;
}

std::string ThumbnailCache::png(const std::string& sha256) {
  {
    const std::lock_guard lock(mutex_);
    if (const auto found = pngs_.find(sha256); found != pngs_.end()) return found->second;
  }
  // Read outside the lock: a large frame takes a while, and other thumbnails need not wait.
  if (!isSha256Hex(sha256) || !store_.verifiedSize(sha256))
    throw ChunkError("chunk " + sha256 + " is missing or damaged");
  std::string png = encodePngPreview(shrinkBeauty(store_.pathOf(sha256), "chunk " + sha256));
  const std::lock_guard lock(mutex_);
  if (pngs_.emplace(sha256, png).second) {
    insertionOrder_.push_back(sha256);
    if (insertionOrder_.size() > capacity_) {
      pngs_.erase(insertionOrder_.front());
      insertionOrder_.pop_front();
    }
  }
  return png;
}

}  // namespace pathfarm::farm
