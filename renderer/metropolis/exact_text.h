#pragma once
// Doubles as text with their exact bits (hexadecimal floating point), for what the farm
// ships between tasks as text: seed pools and chain statistics.
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace pathfarm {

inline std::string exactText(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%a", value);
  return buffer;
}

// Throws std::invalid_argument starting with `what` for a token that is not one number.
inline double parseExactText(const std::string& token, const std::string& what) {
  char* end = nullptr;
  const double value = std::strtod(token.c_str(), &end);
  if (token.empty() || *end != '\0') throw std::invalid_argument(what + ": not a number: '" + token + "'");
  return value;
}

}  // namespace pathfarm
