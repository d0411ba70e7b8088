#include "image/frame_image.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
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

const std::vector<float>& channelOf(const FrameImage& frame, const std::string& name, const std::string& whose) {
  if (!frame.hasChannel(name)) throw std::invalid_argument(whose + " has no channel \"" + name + "\"");
  return frame.channel(name);
}

const std::vector<float>& requireChannel(const FrameImage& frame, const std::string& name, const std::string& file) {
  if (!frame.hasChannel(name)) throw std::invalid_argument(file + ": missing channel \"" + name + "\"");
  return frame.channel(name);
}

void requireSameSize(const FrameImage& a, const FrameImage& b) {
  if (a.width() != b.width() || a.height() != b.height())
    throw std::invalid_argument("the frames differ in size: " + std::to_string(a.width()) + "x" +
                                std::to_string(a.height()) + " against " + std::to_string(b.width()) + "x" +
                                std::to_string(b.height()));
}

void FrameImage::paste(const FrameImage& part, int x0, int y0) {
  if (x0 < 0 || y0 < 0 || x0 + part.width() > width_ || y0 + part.height() > height_)
    throw std::invalid_argument("a " + std::to_string(part.width()) + "x" + std::to_string(part.height()) +
                                " part at (" + std::to_string(x0) + ", " + std::to_string(y0) +
                                ") does not fit a " + std::to_string(width_) + "x" + std::to_string(height_) +
                                " frame");
  for (const std::string& name : part.channelNames()) {
    const std::vector<float>& source = part.channel(name);
    std::vector<float>& target = addChannel(name);
    for (int y = 0; y < part.height(); ++y) {
      const auto from = source.begin() + static_cast<ptrdiff_t>(y) * part.width();
      std::copy(from, from + part.width(),
                target.begin() + (static_cast<ptrdiff_t>(y0 + y) * width_ + x0));
    }
  }
}

std::string FrameImage::firstNonFinite(int firstRow) const {
  for (const std::string& name : names_) {
    const std::vector<float>& plane = planes_.at(name);
    const auto bad = std::find_if(plane.begin(), plane.end(), [](float v) { return !std::isfinite(v); });
    if (bad == plane.end()) continue;
    const auto p = static_cast<size_t>(bad - plane.begin());
    const auto w = static_cast<size_t>(std::max(width_, 1));
    return "channel " + name + " at pixel (" + std::to_string(p % w) + ", " +
           std::to_string(p / w + static_cast<size_t>(std::max(firstRow, 0))) + ")";
  }
  return {};
}

FrameImage FrameImage::crop(int x0, int y0, int width, int height) const {
  if (x0 < 0 || y0 < 0 || width < 0 || height < 0 || x0 + width > width_ || y0 + height > height_)
    throw std::invalid_argument("a " + std::to_string(width) + "x" + std::to_string(height) + " crop at (" +
                                std::to_string(x0) + ", " + std::to_string(y0) + ") does not fit a " +
                                std::to_string(width_) + "x" + std::to_string(height_) + " frame");
  FrameImage part(width, height);
  for (const std::string& name : names_) {
    const std::vector<float>& source = channel(name);
    std::vector<float>& target = part.addChannel(name);
    for (int y = 0; y < height; ++y) {
      const auto from = source.begin() + (static_cast<ptrdiff_t>(y0 + y) * width_ + x0);
      std::copy(from, from + width, target.begin() + static_cast<ptrdiff_t>(y) * width);
    }
  }
  part.attributes_ = attributes_;
  return part;
}

}  // namespace pathfarm
