#pragma once
// A frame as pathfarm moves it around: named float channels of one resolution, in the
// order they were added, plus string attributes. Channel names follow the data
// contract: beauty in "R","G","B", other buffers "<layer>.<buffer>.<channel>" or, for
// frame-wide buffers, "<buffer>.<channel>".
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace pathfarm {

class FrameImage {
 public:
  FrameImage() = default;
  FrameImage(int width, int height) : width_(width), height_(height) {}

  int width() const { return width_; }
  int height() const { return height_; }
  size_t pixelCount() const { return static_cast<size_t>(width_) * static_cast<size_t>(height_); }

  // Adds a zero-filled channel (or returns the existing one).
  std::vector<float>& addChannel(const std::string& name);
  bool hasChannel(const std::string& name) const;
  // Throws std::out_of_range naming the missing channel.
  const std::vector<float>& channel(const std::string& name) const;
  std::vector<float>& channel(const std::string& name);
  const std::vector<std::string>& channelNames() const { return names_; }
  // Removes the channels `drop` names (name -> true) and frees their memory; the others keep their order.
  template <typename Predicate>
  void removeChannels(Predicate drop) {
    std::erase_if(names_, [&](const std::string& name) {
      if (!drop(name)) return false;
      planes_.erase(name);
      return true;
    });
  }

  // Copies every channel of `part` into this frame with its corner at (x0, y0), adding
  // channels this frame lacks; throws std::invalid_argument if it does not fit.
  void paste(const FrameImage& part, int x0, int y0);
  // The pixels [x0, x0 + width) x [y0, y0 + height) of every channel, with the attributes;
  // throws std::invalid_argument if they do not lie inside.
  FrameImage crop(int x0, int y0, int width, int height) const;
  // The first NaN or infinity, as "channel C at pixel (x, y)", or empty when every value
  // is finite: what a task checks before it trusts a chunk another one made.
  // `firstRow`: the row of a larger frame this image's first row is, for the position.
  std::string firstNonFinite(int firstRow = 0) const;

  std::map<std::string, std::string>& attributes() { return attributes_; }
  const std::map<std::string, std::string>& attributes() const { return attributes_; }

 private:
  int width_ = 0, height_ = 0;
  std::vector<std::string> names_;
  std::map<std::string, std::vector<float>> planes_;
  std::map<std::string, std::string> attributes_;
};

// The channel `name` of a frame a caller was given, or std::invalid_argument
// "<whose> has no channel \"<name>\"" when it lacks it: `whose` names the frame for the
// reader ("radiance check: the features' frame"). A missing channel of such a frame is bad
// input, where FrameImage::channel's std::out_of_range would read as a bug.
const std::vector<float>& channelOf(const FrameImage& frame, const std::string& name, const std::string& whose);
// The same for a frame read from a file: "<file>: missing channel \"<name>\"", `file` as
// the reader knows it ("frame_0009.exr").
const std::vector<float>& requireChannel(const FrameImage& frame, const std::string& name, const std::string& file);

// std::invalid_argument "the frames differ in size: WxH against WxH" unless a and b have
// the same resolution.
void requireSameSize(const FrameImage& a, const FrameImage& b);

// The beauty's channels, in order.
inline constexpr const char* kRgbChannels[3] = {"R", "G", "B"};

}  // namespace pathfarm
