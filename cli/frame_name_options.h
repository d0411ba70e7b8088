#pragma once
// --frame-names of `pathfarm local` and `pathfarm fetch` (client/frame_names.h).
#include <CLI/CLI.hpp>

#include <optional>
#include <stdexcept>
#include <string>

#include "cli/usage_parsing.h"
#include "client/frame_names.h"

namespace pathfarm {

inline void addFrameNamesOption(CLI::App* command, std::string& pattern) {
  command->add_option("--frame-names", pattern,
                      "frame file names under the output folder, e.g. \"{shot}/{frame:04d}.exr\" (fields {shot}, "
                      "{id}, {frame}, {frame:0Nd}; default frame_NNNN.exr)");
}

// The template, or nothing when none was given; UsageError when it is malformed.
inline std::optional<farm::FrameNames> frameNamesOf(const std::string& pattern) {
  if (pattern.empty()) return std::nullopt;
  try {
    return farm::FrameNames(pattern);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
}

}  // namespace pathfarm
