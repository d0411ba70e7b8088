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

uint64_t DecodedInputs::frameBytes(const FrameImage& frame) {
  return static_cast<uint64_t>(frame.channelNames().size()) * frame.pixelCount() * sizeof(float);
}

}  // namespace pathfarm::farm
