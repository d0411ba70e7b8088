#pragma once
// A content-addressed store of chunks on disk: a chunk lives at objects/ab/cdef...
// named by its SHA-256. Writes go to a temporary file that is fsynced and renamed, so a
// chunk is either wholly there or absent, and a reader verifies the digest again, so a
// file damaged on disk is noticed rather than served.
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <istream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "image/atomic_file.h"
#include "pathfarm/chunk.pb.h"

namespace pathfarm::farm {

class Sha256;

// A chunk whose bytes do not match its digest or size, or that cannot be stored.
class ChunkError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A chunk arriving in parts, checked as it comes and never held whole: written to `file`
// (or, with none, only checked), which appears under its name only when the whole matches
// the announced digest and size. Errors are ChunkErrors, "cannot <purpose>: ..." when the
// file cannot be written.
class IncomingChunk {
 public:
  // Throws ChunkError for an announced size beyond `maxBytes` or a digest that is no
  // SHA-256.
  IncomingChunk(const ChunkRef& announced, size_t maxBytes, const std::optional<std::filesystem::path>& file,
                AtomicFileWriter::Sync sync, std::string purpose);
  ~IncomingChunk();
  // Throws ChunkError once the bytes outgrow the announced size, or cannot be written.
  void append(std::string_view part);
  // Throws ChunkError for a short chunk or a digest mismatch; no file appears then.
  ChunkRef commit();

 private:
  [[noreturn]] void fail(const std::exception& e) const;
  ChunkRef announced_;
  AtomicFileWriter::Sync sync_;
  std::string purpose_;
  int64_t received_ = 0;
  std::unique_ptr<Sha256> digest_;
  std::unique_ptr<AtomicFileWriter> file_;
};

class ChunkStore {
 public:
  // A cache (a worker's) skips the fsync of each chunk: it verifies what it reads, so a
  // chunk an OS crash damaged is fetched again; the scheduler's store syncs every chunk.
  enum class Kind { Store, Cache };
  explicit ChunkStore(std::filesystem::path root, Kind kind = Kind::Store);

  // Stores the bytes; if `expected` names a digest or size, the bytes must match it.
  ChunkRef put(const std::string& bytes, const ChunkRef& expected = {});
  bool has(const std::string& sha256) const;
  // Removes the temporaries of chunks whose writer was killed before it finished (a
  // scheduler or worker restarted after a crash); returns how many.
  size_t removeAbandonedWrites();
  // The chunk's bytes, verified; nullopt when absent. A damaged file is removed and
  // reported as absent.
  std::optional<std::string> get(const std::string& sha256) const;
  // Deletes the chunk's file; a chunk that is not there is no error.
  void remove(const std::string& sha256);

  // A chunk arriving in parts, written to disk as it comes (never held whole): stored
  // under its digest only when the whole matches the announced digest and size.
  class Incoming {
   public:
    // Throws ChunkError for an announced size beyond `maxBytes` or a digest that is no
    // SHA-256.
    Incoming(ChunkStore& store, const ChunkRef& announced, size_t maxBytes);
    // Throws ChunkError once the bytes outgrow the announced size, or cannot be written.
    void append(std::string_view part) { chunk_.append(part); }
    // Throws ChunkError for a short chunk or a digest mismatch; nothing is stored then.
    ChunkRef commit();

   private:
    ChunkStore& store_;
    IncomingChunk chunk_;
  };

  // The size of a stored chunk whose digest checks out, reading the file in parts; a
  // damaged file is removed. Nothing for an absent or damaged chunk.
  std::optional<int64_t> verifiedSize(const std::string& sha256) const;
  // Hands a stored chunk's bytes to `part` in pieces of at most `partBytes`, until it
  // returns false (then false). Verify the chunk first (verifiedSize).
  bool readParts(const std::string& sha256, size_t partBytes, const std::function<bool(std::string_view)>& part) const;
  // The file a stored chunk lives in, for a reader that reads it in place (verify the
  // chunk first: verifiedSize). The digest must be a SHA-256 (isSha256Hex).
  std::filesystem::path pathOf(const std::string& sha256) const;
  const std::filesystem::path& root() const { return root_; }
  // Bytes put into and read out of the store since it was opened (the farm's metrics).
  uint64_t bytesIn() const { return bytesIn_; }
  uint64_t bytesOut() const { return bytesOut_; }

 private:
  std::filesystem::path root_;
  AtomicFileWriter::Sync sync_;
  std::atomic<uint64_t> bytesIn_{0};
  mutable std::atomic<uint64_t> bytesOut_{0};
};

bool isSha256Hex(const std::string& text);

// Hands the bytes of `in` to `part` in pieces of at most `partBytes`, until it returns
// false (then false).
bool readStreamParts(std::istream& in, size_t partBytes, const std::function<bool(std::string_view)>& part);
// The digest and size of a file's bytes, read in parts; throws ChunkError when it cannot
// be read.
ChunkRef refOfFile(const std::filesystem::path& file);

}  // namespace pathfarm::farm
