#pragma once
// The scheduler's clock for leases, heartbeats and events: seconds since the epoch (what
// the database stores), read from the wall clock once and advanced by the monotonic clock
// after that. A step of the wall clock (NTP, an operator) then neither expires every lease
// at once nor keeps a dead worker's lease alive; after a restart the clock starts from the
// wall clock again, which is what the stored times were measured against.
#include <chrono>
#include <functional>

namespace pathfarm::farm {

class FarmClock {
 public:
  using WallSource = std::function<std::chrono::system_clock::time_point()>;
  using SteadySource = std::function<std::chrono::steady_clock::time_point()>;

  // The sources are the system's clocks unless a test gives its own.
  explicit FarmClock(WallSource wall = std::chrono::system_clock::now,
                     SteadySource steady = std::chrono::steady_clock::now)
      : steady_(std::move(steady)), wallAtStart_(wall()), steadyAtStart_(steady_()) {}

  double seconds() const {
    return std::chrono::duration<double>(wallAtStart_.time_since_epoch() + (steady_() - steadyAtStart_)).count();
  }

 private:
  SteadySource steady_;
  std::chrono::system_clock::time_point wallAtStart_;
  std::chrono::steady_clock::time_point steadyAtStart_;
};

// The process's farm clock, started at its first use.
inline double farmClockSeconds() {
  static const FarmClock clock;
  return clock.seconds();
}

}  // namespace pathfarm::farm
