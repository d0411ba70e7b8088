#include "image/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>

namespace pathfarm {
namespace {

// A temporary is "<file>.<pid>.<n>.partial".
constexpr std::string_view kPartial = ".partial";

// The writer's process id in a temporary's name, or 0 when the name is no temporary's.
long writerOf(const std::string& name) {
  if (name.size() <= kPartial.size() || name.compare(name.size() - kPartial.size(), kPartial.size(), kPartial) != 0)
    return 0;
  const std::string stem = name.substr(0, name.size() - kPartial.size());
  const size_t counterDot = stem.rfind('.');
  if (counterDot == std::string::npos || counterDot == 0) return 0;
  const size_t pidDot = stem.rfind('.', counterDot - 1);
  if (pidDot == std::string::npos) return 0;
  const std::string pid = stem.substr(pidDot + 1, counterDot - pidDot - 1);
  if (pid.empty() || pid.size() > 9 || pid.find_first_not_of("0123456789") != std::string::npos) return 0;
  return std::stol(pid);
}

}  // namespace

size_t removeAbandonedTemporaries(const std::filesystem::path& folder) {
  size_t removed = 0;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(folder, error)) {
    const long pid = writerOf(entry.path().filename().string());
    // kill(pid, 0) probes without signalling: ESRCH means no such process.
    if (pid > 0 && ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH && std::filesystem::remove(entry.path(), error))
      ++removed;
  }
  return removed;
}

AtomicFileWriter::AtomicFileWriter(std::filesystem::path file) : file_(std::move(file)) {
  // A name of this writer's own: concurrent writers of the same file never share (or
  // remove) each other's temporary, and the last rename wins with complete content.
  static std::atomic<uint64_t> counter{0};
  temporary_ = file_.string() + "." + std::to_string(::getpid()) + "." + std::to_string(counter++) + std::string(kPartial);
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
