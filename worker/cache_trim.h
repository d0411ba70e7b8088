#pragma once
// Keeps a worker's cache folder within a size: input chunks (objects/, oldest stored
// first: a chunk gone is fetched again) and rebuilt scenes (scenes/, least recently used
// first). Nothing touched within `minAge` is removed, since a task may be reading it.
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <mutex>

namespace pathfarm::farm {

struct TrimResult {
  uint64_t bytesBefore = 0, bytesRemoved = 0;
  int entriesRemoved = 0;
};

TrimResult trimCache(const std::filesystem::path& cache, uint64_t maxBytes, std::chrono::seconds minAge);

// trimCache at most once per `period`, from any thread.
class CacheBound {
 public:
  CacheBound(std::filesystem::path cache, uint64_t maxBytes, std::chrono::seconds period = std::chrono::seconds(30));
  void maybeTrim();

 private:
  std::filesystem::path cache_;
  uint64_t maxBytes_;
  std::chrono::seconds period_;
  std::mutex mutex_;
  std::chrono::steady_clock::time_point last_{};
};

}  // namespace pathfarm::farm
