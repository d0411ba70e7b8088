#pragma once
// A worker's file that lives as long as someone holds it: an output too large to keep in
// memory (an assembled frame), removed once it was delivered or dropped.
#include <filesystem>
#include <string>
#include <system_error>
#include <utility>

namespace pathfarm::farm {

class ScratchFile {
 public:
  explicit ScratchFile(std::filesystem::path path) : path_(std::move(path)) {}
  ~ScratchFile() {
    std::error_code ignored;
    std::filesystem::remove(path_, ignored);
  }
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;

  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// Scratch files are named "<process id>-<name>" in their folder. Removes those of
// processes that no longer run: a worker killed while it held one left it behind, and
// workers may share a folder.
void removeOrphanedScratchFiles(const std::filesystem::path& folder);
// A file name in `folder` for `name` that no other process uses.
std::filesystem::path scratchPathFor(const std::filesystem::path& folder, const std::string& name);

}  // namespace pathfarm::farm
