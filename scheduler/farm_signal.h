#pragma once
// Wakes whoever waits for the farm to change: workers long-polling for a task, clients
// watching a shot. Waiters wake on a change or when their timeout passes.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>

namespace pathfarm::farm {

class FarmSignal {
 public:
  void notify() {
    {
      const std::lock_guard lock(mutex_);
      ++generation_;
    }
    changed_.notify_all();
  }
  // Waits until a notify() after `seen`, or the timeout; returns the generation to pass next.
  uint64_t waitFor(uint64_t seen, std::chrono::milliseconds timeout) {
    std::unique_lock lock(mutex_);
    changed_.wait_for(lock, timeout, [&] { return generation_ != seen; });
    return generation_;
  }
  uint64_t generation() {
    const std::lock_guard lock(mutex_);
    return generation_;
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  uint64_t generation_ = 0;
};

}  // namespace pathfarm::farm
