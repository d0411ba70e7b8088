#include "worker/cache_trim.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <vector>

namespace pathfarm::farm {
namespace {

namespace fs = std::filesystem;

struct Entry {
  fs::path path;
  uint64_t bytes = 0;
  fs::file_time_type used;
};

uint64_t bytesUnder(const fs::path& folder) {
  uint64_t total = 0;
  std::error_code error;
  for (fs::recursive_directory_iterator it(folder, error), end; !error && it != end; it.increment(error)) {
    std::error_code sizeError;
    if (it->is_regular_file(sizeError)) total += it->file_size(sizeError);
  }
  return total;
}

// Chunk files under objects/ and scene folders under scenes/, each with its size and last use.
std::vector<Entry> entriesOf(const fs::path& cache) {
  std::vector<Entry> entries;
  std::error_code error;
  for (fs::recursive_directory_iterator it(cache / "objects", error), end; !error && it != end; it.increment(error)) {
    std::error_code e;
    if (it->is_regular_file(e)) entries.push_back({it->path(), it->file_size(e), it->last_write_time(e)});
  }
  for (fs::directory_iterator it(cache / "scenes", error), end; !error && it != end; it.increment(error)) {
    std::error_code e;
    if (it->is_directory(e)) entries.push_back({it->path(), bytesUnder(it->path()), it->last_write_time(e)});
  }
  return entries;
}

}  // namespace

TrimResult trimCache(const fs::path& cache, uint64_t maxBytes, std::chrono::seconds minAge) {
  TrimResult result;
  // Summed first, without listing: a cache of millions of small tiles under its bound is
  // not held in memory as a list every time it is checked.
  result.bytesBefore = bytesUnder(cache / "objects") + bytesUnder(cache / "scenes");
  if (result.bytesBefore <= maxBytes) return result;
  std::vector<Entry> entries = entriesOf(cache);
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) { return a.used < b.used; });
  const auto youngest = fs::file_time_type::clock::now() - minAge;
  uint64_t bytes = result.bytesBefore;
  for (const Entry& entry : entries) {
    if (bytes <= maxBytes || entry.used > youngest) break;
    std::error_code error;
    fs::remove_all(entry.path, error);
    if (error) continue;
    bytes -= entry.bytes;
    result.bytesRemoved += entry.bytes;
    ++result.entriesRemoved;
  }
  return result;
}

CacheBound::CacheBound(fs::path cache, uint64_t maxBytes, std::chrono::seconds period)
    : cache_(std::move(cache)), maxBytes_(maxBytes), period_(period) {}

void CacheBound::maybeTrim() {
  const std::lock_guard lock(mutex_);
  const auto now = std::chrono::steady_clock::now();
  if (last_ != std::chrono::steady_clock::time_point{} && now - last_ < period_) return;
  last_ = now;
  const TrimResult trimmed = trimCache(cache_, maxBytes_, std::chrono::minutes(10));
  if (trimmed.entriesRemoved > 0)
    spdlog::info("cache {}: removed {} entries ({:.1f} MB) to stay under {:.1f} MB", cache_.string(),
                 trimmed.entriesRemoved, static_cast<double>(trimmed.bytesRemoved) / 1e6,
                 static_cast<double>(maxBytes_) / 1e6);
}

}  // namespace pathfarm::farm
