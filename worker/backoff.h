#pragma once
#include <algorithm>
#include <chrono>
#include <thread>

namespace pathfarm::farm {

// Sleeps with doubling backoff between attempts, from 100 ms up to 5 s.
class Backoff {
 public:
  void sleep() {
    std::this_thread::sleep_for(delay_);
    delay_ = std::min(delay_ * 2, std::chrono::milliseconds(5000));
  }
  void reset() { delay_ = std::chrono::milliseconds(100); }

 private:
  std::chrono::milliseconds delay_{100};
};

}  // namespace pathfarm::farm
