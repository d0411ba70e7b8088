#pragma once
// A terminal progress bar on stderr, safe to update from many threads. When stderr is
// not a terminal (a log file, CI), it prints nothing and leaves reporting to the log.
#include <chrono>
#include <mutex>
#include <string>

namespace pathfarm {

class ProgressBar {
 public:
  explicit ProgressBar(std::string label);
  ~ProgressBar();  // finishes the line
  void update(size_t done, size_t total);

 private:
  std::string label_;
  bool enabled_;
  std::mutex mutex_;
  std::chrono::steady_clock::time_point start_, lastDraw_{};
};

}  // namespace pathfarm
