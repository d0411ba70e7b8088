#pragma once
#include <algorithm>
#include <chrono>
#include <functional>
#include <thread>

namespace pathfarm::farm {

// Waits with doubling backoff between attempts, from 100 ms up to 5 s. The wait itself is
// `pause` (a plain sleep by default; SchedulerLink::pause ends it early once the scheduler
// can be reached again).
class Backoff {
 public:
  using Pause = std::function<void(std::chrono::milliseconds)>;
  explicit Backoff(Pause pause = [](std::chrono::milliseconds delay) { std::this_thread::sleep_for(delay); })
      : pause_(std::move(pause)) {}

  void sleep() {
    pause_(delay_);
    delay_ = std::min(delay_ * 2, std::chrono::milliseconds(5000));
  }
  void reset() { delay_ = std::chrono::milliseconds(100); }

 private:
  Pause pause_;
  std::chrono::milliseconds delay_{100};
};

}  // namespace pathfarm::farm
