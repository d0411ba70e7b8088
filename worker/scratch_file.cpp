#include "worker/scratch_file.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>

namespace pathfarm::farm {

void removeOrphanedScratchFiles(const std::filesystem::path& folder) {
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(folder, error)) {
    const std::string name = entry.path().filename().string();
    const size_t dash = name.find('-');
    if (dash == 0 || dash > 9 || name.find_first_not_of("0123456789") != dash) continue;  // not "<pid>-..."
    const long pid = std::stol(name.substr(0, dash));
    // kill(pid, 0) probes without signalling: ESRCH means no such process.
    if (pid > 0 && kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) std::filesystem::remove(entry.path(), error);
  }
}

std::filesystem::path scratchPathFor(const std::filesystem::path& folder, const std::string& name) {
  std::filesystem::create_directories(folder);
  return folder / (std::to_string(getpid()) + "-" + name);
}

}  // namespace pathfarm::farm
