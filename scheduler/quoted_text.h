#pragma once
// What a caller sent, quoted for an error message or a log line: printable ASCII as it is,
// anything else (control characters, a newline that would forge a log line, bytes of
// binary or non-ASCII text) as \xNN, and at most kQuotedBytes bytes of it, the rest
// counted. A hostile request then cannot make an answer or the log large or misleading.
#include <cstddef>
#include <string>
#include <string_view>

namespace pathfarm::farm {

inline constexpr size_t kQuotedBytes = 80;

// (Not `quoted`: std::quoted would be found for std::string arguments.)
std::string quotedInput(std::string_view text);

}  // namespace pathfarm::farm
