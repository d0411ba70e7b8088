#pragma once
// SHA-256 digests (OpenSSL), as lowercase hex: chunk names and integrity checks.
#include <string>
#include <string_view>

namespace pathfarm::farm {

std::string sha256Hex(std::string_view bytes);

}  // namespace pathfarm::farm
