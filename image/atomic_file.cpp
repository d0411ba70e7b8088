#include "image/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>

namespace pathfarm {

void writeFileAtomically(const std::filesystem::path& file, const std::string& bytes) {
  // A name of this writer's own: concurrent writers of the same file never share (or
  // remove) each other's temporary, and the last rename wins with complete content.
  static std::atomic<uint64_t> counter{0};
  const std::string temporary =
      file.string() + "." + std::to_string(::getpid()) + "." + std::to_string(counter++) + ".partial";
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error(file.string() + ": cannot write: " + std::strerror(errno));
  size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const std::string reason = std::strerror(errno);
      ::close(fd);
      ::unlink(temporary.c_str());
      throw std::runtime_error(file.string() + ": cannot write: " + reason);
    }
    written += static_cast<size_t>(n);
  }
  const bool synced = ::fsync(fd) == 0;
  ::close(fd);
  if (!synced || ::rename(temporary.c_str(), file.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    ::unlink(temporary.c_str());
    throw std::runtime_error(file.string() + ": cannot move the finished file into place: " + reason);
  }
}

}  // namespace pathfarm
