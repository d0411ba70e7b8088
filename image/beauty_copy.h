#pragma once
// A frame's beauty alone: its R, G and B channels and its attributes, for viewers that
// read a multi-layer EXR only when every channel belongs to a layer. Blender 3.4 is one:
// it refuses a file whose plain R, G, B (the frames' contract) sit beside
// <layer>.<buffer>.<channel> channels, and reads this copy.
#include <filesystem>

namespace pathfarm {

// Reads `frame` and writes `copy` a strip of rows at a time, so a frame of any size fits.
// Throws ExrError naming the file that could not be read or written.
void writeBeautyCopy(const std::filesystem::path& frame, const std::filesystem::path& copy);

}  // namespace pathfarm
