#include "image/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>

namespace pathfarm {

AtomicFileWriter::AtomicFileWriter(std::filesystem::path file) : file_(std::move(file)) {
  // A name of this writer's own: concurrent writers of the same file never share (or
  // remove) each other's temporary, and the last rename wins with complete content.
  static std::atomic<uint64_t> counter{0};
  temporary_ = file_.string() + "." + std::to_string(::getpid()) + "." + std::to_string(counter++) + ".partial";
  fd_ = ::open(temporary_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) throw std::runtime_error(file_.string() + ": cannot write: " + std::strerror(errno));
}

AtomicFileWriter::~AtomicFileWriter() {
  if (fd_ < 0) return;
  ::close(fd_);
  ::unlink(temporary_.c_str());
}

void AtomicFileWriter::fail(const std::string& what) {
  const std::string reason = std::strerror(errno);
  ::close(fd_);
  fd_ = -1;
  ::unlink(temporary_.c_str());
  throw std::runtime_error(file_.string() + ": " + what + ": " + reason);
}

void AtomicFileWriter::append(std::string_view bytes) {
  if (fd_ < 0) throw std::logic_error(file_.string() + ": written after it was committed or failed");
  size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = ::write(fd_, bytes.data() + written, bytes.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail("cannot write");
    written += static_cast<size_t>(n);
  }
}

void AtomicFileWriter::commit(Sync sync) {
  if (fd_ < 0) throw std::logic_error(file_.string() + ": committed after it was committed or failed");
  if ((sync == Sync::Yes && ::fsync(fd_) != 0) || ::rename(temporary_.c_str(), file_.c_str()) != 0)
    fail("cannot move the finished file into place");
  ::close(fd_);
  fd_ = -1;
}

void writeFileAtomically(const std::filesystem::path& file, const std::string& bytes, AtomicFileWriter::Sync sync) {
  AtomicFileWriter writer(file);
  writer.append(bytes);
  writer.commit(sync);
}

}  // namespace pathfarm
