#include "renderer/metropolis/block_result.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace pathfarm {

std::vector<FrameImage> mergeBlocks(FrameWindow window, int blocks, std::vector<BlockResult> results) {
  std::sort(results.begin(), results.end(), [](const BlockResult& a, const BlockResult& b) { return a.block < b.block; });
  if (results.size() != static_cast<size_t>(blocks))
    throw std::invalid_argument("merging " + std::to_string(results.size()) + " block results, expected " +
                                std::to_string(blocks));
  for (int b = 0; b < blocks; ++b) {
    const BlockResult& result = results[static_cast<size_t>(b)];
    if (result.block != b) throw std::invalid_argument("block " + std::to_string(b) + " is missing or repeated");
    if (result.frames.size() != static_cast<size_t>(window.count))
      throw std::invalid_argument("block " + std::to_string(b) + " does not hold one image per frame of the window");
  }
  std::vector<FrameImage> merged;
  MutationStats stats;
  for (const BlockResult& result : results) stats.add(result.stats);
  for (size_t f = 0; f < static_cast<size_t>(window.count); ++f) {
    const FrameImage& first = results.front().frames[f];
    FrameImage image(first.width(), first.height());
    for (const char* name : {"R", "G", "B"}) {
      std::vector<float>& out = image.addChannel(name);
      std::vector<double> sum(out.size(), 0.0);
      for (const BlockResult& result : results) {
        const std::vector<float>& part = result.frames[f].channel(name);
        if (part.size() != sum.size()) throw std::invalid_argument("block images of different sizes");
        for (size_t i = 0; i < sum.size(); ++i) sum[i] += part[i];
      }
      for (size_t i = 0; i < sum.size(); ++i) out[i] = static_cast<float>(sum[i]);
    }
    stats.writeAttributes(image);
    merged.push_back(std::move(image));
  }
  return merged;
}

}  // namespace pathfarm
