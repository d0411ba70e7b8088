#pragma once
// Files that are either wholly written or absent: the bytes go to a temporary file of
// this writer's own, which is fsynced and renamed into place. Frames, chunks and fetched
// outputs are written this way, so a crash never leaves half a file under the real name.
#include <filesystem>
#include <stdexcept>
#include <string>

namespace pathfarm {

// Throws std::runtime_error naming the file when it cannot be written.
void writeFileAtomically(const std::filesystem::path& file, const std::string& bytes);

}  // namespace pathfarm
