#include "scheduler/exclusive_database.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>

namespace pathfarm::farm {

ExclusiveDatabase::ExclusiveDatabase(const std::filesystem::path& database) {
  const std::string lockFile = database.string() + ".scheduler-lock";
  descriptor_ = ::open(lockFile.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (descriptor_ < 0) throw std::runtime_error(lockFile + ": cannot open: " + std::strerror(errno));
  if (::flock(descriptor_, LOCK_EX | LOCK_NB) != 0) {
    char holder[32] = {};
    const ssize_t n = ::pread(descriptor_, holder, sizeof holder - 1, 0);
    ::close(descriptor_);
    throw std::runtime_error(database.string() + " is in use by another scheduler" +
                             (n > 0 ? " (pid " + std::string(holder, static_cast<size_t>(n)) + ")" : std::string()) +
                             "; one database serves one scheduler");
  }
  const std::string pid = std::to_string(::getpid());
  if (::ftruncate(descriptor_, 0) != 0 || ::pwrite(descriptor_, pid.data(), pid.size(), 0) < 0) {
    // The pid only makes the refusal clearer; the lock holds without it.
  }
}

ExclusiveDatabase::~ExclusiveDatabase() {
  if (descriptor_ >= 0) ::close(descriptor_);  // releases the lock
}

}  // namespace pathfarm::farm
