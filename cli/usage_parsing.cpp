#include "cli/usage_parsing.h"

#include <cstdio>

namespace pathfarm {

std::pair<int64_t, int64_t> parseFrames(const std::string& text) {
  const auto colon = text.find(':');
  try {
    size_t used = 0;
    const int64_t first = std::stoll(text.substr(0, colon), &used);
    if (used != (colon == std::string::npos ? text.size() : colon)) throw std::invalid_argument(text);
    int64_t last = first;
    if (colon != std::string::npos) {
      const std::string tail = text.substr(colon + 1);
      last = std::stoll(tail, &used);
      if (used != tail.size()) throw std::invalid_argument(text);
    }
    if (first < 0 || last < first) throw std::invalid_argument(text);
    return {first, last};
  } catch (const std::logic_error&) {
    throw UsageError("--frames \"" + text + "\": expected FIRST:LAST with 0 <= FIRST <= LAST");
  }
}

std::pair<int, int> parseResolution(const std::string& text) {
  int width = 0, height = 0;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%dx%d%c", &width, &height, &tail) != 2 || width < 1 || height < 1 ||
      width > 16384 || height > 16384)
    throw UsageError("--res \"" + text + "\": expected WIDTHxHEIGHT, each from 1 to 16384");
  return {width, height};
}

}  // namespace pathfarm
