#pragma once
// What the fuzz targets share (bench/fuzz.sh builds them).
#include <spdlog/spdlog.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string_view>

namespace pathfarm::fuzz {

// The readers log warnings; a fuzzer feeds them millions of inputs.
inline void silenceLogs() {
  static const bool silenced = [] {
    spdlog::set_level(spdlog::level::off);
    return true;
  }();
  (void)silenced;
}

inline std::string_view asText(const uint8_t* data, size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// A refused input is a correct outcome; with PATHFARM_FUZZ_VERBOSE set (to check what
// the seeds reach) its message is printed.
inline void noteRefusal(const std::exception& e) {
  static const bool verbose = std::getenv("PATHFARM_FUZZ_VERBOSE") != nullptr;
  if (verbose) std::fprintf(stderr, "refused: %s\n", e.what());
}

// fuzz/assets, the folder an input is read as if it were in: the meshes, texture, sky and
// glTF file a scene may name, and the scenes a shot may name. bench/fuzz.sh compiles its
// absolute path in, so a finding runs again from any folder.
inline std::filesystem::path assetFolder() { return PATHFARM_FUZZ_ASSETS; }

}  // namespace pathfarm::fuzz
