#include "image/frame_image.h"

#include <utility>

namespace pathfarm {

std::vector<float>& FrameImage::addChannel(const std::string& name) {
  auto [it, inserted] = planes_.try_emplace(name);
  if (inserted) {
    it->second.assign(pixelCount(), 0.0f);
    names_.push_back(name);
  }
  return it->second;
}

bool FrameImage::hasChannel(const std::string& name) const { return planes_.count(name) > 0; }

const std::vector<float>& FrameImage::channel(const std::string& name) const {
  const auto it = planes_.find(name);
  if (it == planes_.end()) throw std::out_of_range("the frame has no channel \"" + name + "\"");
  return it->second;
}

std::vector<float>& FrameImage::channel(const std::string& name) {
  return const_cast<std::vector<float>&>(std::as_const(*this).channel(name));
}

}  // namespace pathfarm
