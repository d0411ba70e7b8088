#pragma once
// One scheduler per database: two schedulers on the same farm state would lease the same
// tasks twice and overwrite each other's decisions. The lock is an flock on a file beside
// the database (not on the database itself: closing any other descriptor of that file
// would drop SQLite's own POSIX locks), held for the scheduler's lifetime and released by
// the kernel if the process dies, so a killed scheduler can be restarted at once.
#include <filesystem>

namespace pathfarm::farm {

class ExclusiveDatabase {
 public:
  // Throws std::runtime_error naming the database (and the holder's pid) when another
  // scheduler has it.
  explicit ExclusiveDatabase(const std::filesystem::path& database);
  ~ExclusiveDatabase();
  ExclusiveDatabase(const ExclusiveDatabase&) = delete;
  ExclusiveDatabase& operator=(const ExclusiveDatabase&) = delete;

 private:
  int descriptor_ = -1;
};

}  // namespace pathfarm::farm
