#pragma once
// A child process started from an argument list, stopped politely (SIGTERM, then
// SIGKILL after a grace period) when it goes out of scope, so no test or local farm
// leaves processes behind.
#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace pathfarm::farm {

class ChildProcess {
 public:
  // Starts argv[0] (a path) with the given arguments; stdout and stderr go to `logFile`
  // when one is named. Extra environment entries are "NAME=value". Throws on failure.
  ChildProcess(const std::vector<std::string>& argv, const std::string& logFile = "",
               const std::vector<std::string>& environment = {});
  ~ChildProcess();
  ChildProcess(ChildProcess&& other) noexcept;
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  pid_t pid() const { return pid_; }
  void signal(int signalNumber) const;
  // Waits up to `timeout` for the exit; the exit status (or 128 + signal) if it ended.
  std::optional<int> wait(std::chrono::milliseconds timeout);
  // SIGTERM, wait up to `grace`, then SIGKILL; returns the exit status.
  int stop(std::chrono::milliseconds grace = std::chrono::seconds(10));

 private:
  pid_t pid_ = -1;
  std::optional<int> status_;
};

// The running executable's own path (/proc/self/exe), to start more of itself.
std::string currentExecutable();

}  // namespace pathfarm::farm
