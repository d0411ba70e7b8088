#pragma once
// Frame file names from a template, for `pathfarm local` and `pathfarm fetch`
// (--frame-names): "{shot}/{frame:04d}.exr" names frame 12 of shot "dolly"
// "dolly/0012.exr", relative to the output folder. Fields: {shot} the shot's name, {id}
// its id, {frame} the frame number, {frame:0Nd} the number zero-padded to N digits (1-9).
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace pathfarm::farm {

class FrameNames {
 public:
  // Throws std::invalid_argument naming what is wrong: an unknown or unclosed field, no
  // {frame}, a name that is absolute or climbs out of the folder with "..".
  explicit FrameNames(std::string pattern);

  std::filesystem::path nameOf(int64_t frame, const std::string& shot, int64_t id) const;

 private:
  std::string pattern_;
};

// Moves fetched frames (frame_NNNN.exr, as `fetch` writes them) within `folder` to their
// names; returns the new paths in the same order.
std::vector<std::filesystem::path> renameFrames(const std::vector<std::filesystem::path>& frames,
                                                const std::filesystem::path& folder, const FrameNames& names,
                                                const std::string& shot, int64_t id);

}  // namespace pathfarm::farm
