#include "worker/decoded_inputs.h"

namespace pathfarm::farm {

std::shared_ptr<const FrameImage> DecodedInputs::find(const std::string& sha256) {
  const std::lock_guard lock(mutex_);
  const auto found = bySha_.find(sha256);
  if (found == bySha_.end()) return nullptr;
  recent_.splice(recent_.begin(), recent_, found->second);
  return found->second->frame;
}

void DecodedInputs::keep(const std::string& sha256, std::shared_ptr<const FrameImage> frame) {
  const uint64_t bytes = frameBytes(*frame);
  const std::lock_guard lock(mutex_);
  if (bytes > maxBytes_ || bySha_.count(sha256) > 0) return;
  while (!recent_.empty() && bytes_ + bytes > maxBytes_) {
    bytes_ -= recent_.back().bytes;
    bySha_.erase(recent_.back().sha256);
    recent_.pop_back();
  }
  recent_.push_front({sha256, std::move(frame), bytes});
  bySha_[sha256] = recent_.begin();
  bytes_ += bytes;
}

uint64_t DecodedInputs::bytes() const {
  const std::lock_guard lock(mutex_);
  return bytes_;
}

size_t DecodedInputs::size() const {
  const std::lock_guard lock(mutex_);
  return recent_.size();
}

namespace {

// What an entry costs besides its planes' floats, estimated on the high side: per channel
// its name (in the frame's list and map) and its vector; per attribute its key and value;
// and the entry itself (list and hash-map nodes, the digest, the frame object). An 8-pixel
// tile's floats are about a third of what keeping it takes: counting only the floats, a
// worker reading millions of tiles held three times its budget.
constexpr uint64_t kPerChannelBytes = 192;
constexpr uint64_t kPerAttributeBytes = 128;
constexpr uint64_t kPerEntryBytes = 512;

}  // namespace

uint64_t DecodedInputs::frameBytes(const FrameImage& frame) {
  return frameBytes(frame.pixelCount(), frame.channelNames(), frame.attributes());
}

uint64_t DecodedInputs::frameBytes(size_t pixels, const std::vector<std::string>& channels,
                                   const std::map<std::string, std::string>& attributes) {
  uint64_t bytes = kPerEntryBytes + static_cast<uint64_t>(channels.size()) * pixels * sizeof(float);
  for (const std::string& name : channels) bytes += kPerChannelBytes + 2 * name.size();
  for (const auto& [key, value] : attributes) bytes += kPerAttributeBytes + key.size() + value.size();
  return bytes;
}

}  // namespace pathfarm::farm
