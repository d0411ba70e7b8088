#pragma once
// Option values the CLI reads the same way in every command: frame ranges and resolutions.
// A malformed one throws UsageError naming the option.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

namespace pathfarm {

class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// "A:B" (inclusive) or "A", for --frames.
std::pair<int64_t, int64_t> parseFrames(const std::string& text);

// "WxH", for --res.
std::pair<int, int> parseResolution(const std::string& text);

}  // namespace pathfarm
