#pragma once
// Files that are either wholly written or absent: the bytes go to a temporary file of
// this writer's own, which is fsynced and renamed into place. Frames, chunks and fetched
// outputs are written this way, so a crash never leaves half a file under the real name.
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

namespace pathfarm {

// A file written in pieces (a chunk as it arrives) that appears whole or not at all. A
// writer destroyed before commit() removes its temporary. Throws std::runtime_error
// naming the file when it cannot be written.
class AtomicFileWriter {
 public:
  explicit AtomicFileWriter(std::filesystem::path file);
  ~AtomicFileWriter();
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;

  void append(std::string_view bytes);
  // Fsyncs the bytes (unless told not to: a cache that verifies what it reads may lose a
  // file to an OS crash) and renames them into place.
  enum class Sync { Yes, No };
  void commit(Sync sync = Sync::Yes);

 private:
  [[noreturn]] void fail(const std::string& what);
  std::filesystem::path file_;
  std::string temporary_;
  int fd_ = -1;
};

// Removes from `folder` (not below it) the temporaries of writers whose process is gone
// (killed before they committed or cleaned up); returns how many. Those of live processes
// stay: they may still commit.
size_t removeAbandonedTemporaries(const std::filesystem::path& folder);

void writeFileAtomically(const std::filesystem::path& file, const std::string& bytes,
                         AtomicFileWriter::Sync sync = AtomicFileWriter::Sync::Yes);

}  // namespace pathfarm
