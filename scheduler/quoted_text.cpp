#include "scheduler/quoted_text.h"

#include <cstdio>

namespace pathfarm::farm {

std::string quotedInput(std::string_view text) {
  std::string out = "\"";
  for (const char c : text.substr(0, kQuotedBytes)) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte < 0x7f && c != '"' && c != '\\') {
      out += c;
    } else {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\x%02x", byte);
      out += escaped;
    }
  }
  out += '"';
  if (text.size() > kQuotedBytes) out += " (" + std::to_string(text.size() - kQuotedBytes) + " more bytes)";
  return out;
}

}  // namespace pathfarm::farm
