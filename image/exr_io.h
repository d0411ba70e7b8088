#pragma once
// Multi-layer OpenEXR frames: every channel of a FrameImage as 32-bit float, ZIP
// compressed, attributes as string header attributes. Writes are atomic (a temporary
// file renamed into place), so a reader never sees half a frame.
#include <filesystem>
#include <stdexcept>

#include "image/frame_image.h"

namespace pathfarm {

class ExrError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

void writeExr(const std::filesystem::path& file, const FrameImage& frame);
// Reads every channel as float. A missing, truncated or corrupted file throws ExrError
// naming the file.
FrameImage readExr(const std::filesystem::path& file);

}  // namespace pathfarm
