#include "scheduler/thumbnails.h"

#include <algorithm>

#include "image/exr_io.h"
#include "image/png_preview.h"

namespace pathfarm::farm {

FrameImage shrinkBeauty(const FrameImage& frame, int maxEdge) {
  const int longest = std::max(frame.width(), frame.height());
  const int factor = std::max(1, (longest + maxEdge - 1) / maxEdge);
  const int width = (frame.width() + factor - 1) / factor;
  const int height = (frame.height() + factor - 1) / factor;
  FrameImage small(width, height);
  for (const char* name : {"R", "G", "B"}) {
    const std::vector<float>& in = frame.channel(name);
    std::vector<float>& out = small.addChannel(name);
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const int x1 = std::min(frame.width(), (x + 1) * factor), y1 = std::min(frame.height(), (y + 1) * factor);
        double sum = 0;
        for (int sy = y * factor; sy < y1; ++sy)
          for (int sx = x * factor; sx < x1; ++sx) sum += in[static_cast<size_t>(sy) * frame.width() + sx];
        const int count = (x1 - x * factor) * (y1 - y * factor);
        out[static_cast<size_t>(y) * width + x] = static_cast<float>(sum / count);
      }
    }
  }
  return small;
}

std::string ThumbnailCache::png(const std::string& sha256) {
  {
    const std::lock_guard lock(mutex_);
    if (const auto found = pngs_.find(sha256); found != pngs_.end()) return found->second;
  }
  // Decoded outside the lock: a large frame takes a while, and other thumbnails need not wait.
  const auto bytes = store_.get(sha256);
  if (!bytes) throw ChunkError("chunk " + sha256 + " is missing or damaged");
  std::string png = encodePngPreview(shrinkBeauty(decodeExr(*bytes, "chunk " + sha256)));
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
