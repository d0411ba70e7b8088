#pragma once
// Decoded input chunks a worker keeps in memory between tasks. A keyframe of a dui shot
// is the input of a dozen tasks: the irradiance flows of both its intervals, one per
// component, and the interpolation of every frame between its neighbours. Decoding its
// 150-odd channels costs more than most of those tasks' own work, so the frames stay
// decoded, least recently used first out, within a byte budget. Chunks are named by their
// content's digest, so a kept frame is never stale.
#include <cstdint>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

#include "image/frame_image.h"

namespace pathfarm::farm {

class DecodedInputs {
 public:
  explicit DecodedInputs(uint64_t maxBytes) : maxBytes_(maxBytes) {}

  // The frame kept under `sha256`, or null; a hit becomes the most recently used.
  std::shared_ptr<const FrameImage> find(const std::string& sha256);
  // Keeps `frame` (unless it alone exceeds the budget), dropping the least recently used
  // frames until the rest fit.
  void keep(const std::string& sha256, std::shared_ptr<const FrameImage> frame);

  uint64_t bytes() const;
  size_t size() const;
  // Whether a frame that takes `frameBytes` to keep is small enough to be kept at all.
  bool couldKeep(uint64_t frameBytes) const { return frameBytes <= maxBytes_; }

  // The memory keeping a frame takes: its planes and their bookkeeping.
  static uint64_t frameBytes(const FrameImage& frame);
  // The same of a frame known by its pixels, channels and attributes (a file's header).
  static uint64_t frameBytes(size_t pixels, const std::vector<std::string>& channels,
                             const std::map<std::string, std::string>& attributes);

 private:
  struct Entry {
    std::string sha256;
    std::shared_ptr<const FrameImage> frame;
    uint64_t bytes = 0;
  };

  uint64_t maxBytes_;
  mutable std::mutex mutex_;
  std::list<Entry> recent_;  // most recently used first
  std::unordered_map<std::string, std::list<Entry>::iterator> bySha_;
  uint64_t bytes_ = 0;
};

}  // namespace pathfarm::farm
