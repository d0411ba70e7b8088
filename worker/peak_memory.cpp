#include "worker/peak_memory.h"

#include <malloc.h>

#include <fstream>
#include <sstream>
#include <string>

namespace pathfarm::farm {

bool restartPeakResident() {
  // The memory earlier tasks freed goes back to the system first: glibc keeps freed pages
  // of its arenas, and without this a task's peak would start at the largest one before it.
  malloc_trim(0);
  std::ofstream refs("/proc/self/clear_refs");
  refs << "5";
  refs.flush();
  return static_cast<bool>(refs);
}

std::optional<uint64_t> peakResidentBytes() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmHWM:", 0) != 0) continue;
    std::istringstream fields(line.substr(6));
    uint64_t kib = 0;
    if (fields >> kib) return kib * 1024;
  }
  return std::nullopt;
}

}  // namespace pathfarm::farm
