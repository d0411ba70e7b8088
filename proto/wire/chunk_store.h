#pragma once
// A content-addressed store of chunks on disk: a chunk lives at objects/ab/cdef...
// named by its SHA-256. Writes go to a temporary file that is fsynced and renamed, so a
// chunk is either wholly there or absent, and a reader verifies the digest again, so a
// file damaged on disk is noticed rather than served.
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>

#include "pathfarm/chunk.pb.h"

namespace pathfarm::farm {

// A chunk whose bytes do not match its digest or size, or that cannot be stored.
class ChunkError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class ChunkStore {
 public:
  explicit ChunkStore(std::filesystem::path root);

  // Stores the bytes; if `expected` names a digest or size, the bytes must match it.
  ChunkRef put(const std::string& bytes, const ChunkRef& expected = {});
  bool has(const std::string& sha256) const;
  // The chunk's bytes, verified; nullopt when absent. A damaged file is removed and
  // reported as absent.
  std::optional<std::string> get(const std::string& sha256) const;
  // Deletes the chunk's file; a chunk that is not there is no error.
  void remove(const std::string& sha256);
  const std::filesystem::path& root() const { return root_; }
  // Bytes put into and read out of the store since it was opened (the farm's metrics).
  uint64_t bytesIn() const { return bytesIn_; }
  uint64_t bytesOut() const { return bytesOut_; }

 private:
  std::filesystem::path pathOf(const std::string& sha256) const;
  std::filesystem::path root_;
  std::atomic<uint64_t> bytesIn_{0};
  mutable std::atomic<uint64_t> bytesOut_{0};
};

bool isSha256Hex(const std::string& text);

}  // namespace pathfarm::farm
