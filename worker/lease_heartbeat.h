#pragma once
// Renews a slot's lease while its task runs and its output uploads, from one thread the
// slot keeps for its whole life. Two threads per task (std::async for the work and for the
// upload) cost more than a small task itself: without them, a frame of 8-pixel tiles takes
// 40 % less CPU on a local farm (docs/performance.md, "Farm efficiency").
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>

#include "worker/scheduler_link.h"

namespace pathfarm::farm {

class LeaseHeartbeat {
 public:
  LeaseHeartbeat(SchedulerLink& link, std::chrono::milliseconds period);
  ~LeaseHeartbeat();
  LeaseHeartbeat(const LeaseHeartbeat&) = delete;
  LeaseHeartbeat& operator=(const LeaseHeartbeat&) = delete;

  // While a Renewal lives, the attempt is renewed every period with `progress`; a lease
  // the scheduler no longer keeps sets `abandon`, and so does a lease left unrenewed for
  // longer than its lifetime (`lifetimeSeconds` from the lease, then from each renewal):
  // with its scheduler out of reach, a task would otherwise wait for it forever, though
  // the lease is gone once the scheduler runs again. Its end waits for a renewal in
  // flight, so that `progress` and `abandon` may end with it.
  class Renewal {
   public:
    explicit Renewal(LeaseHeartbeat& owner) : owner_(owner) {}
    ~Renewal() { owner_.disarm(); }
    Renewal(const Renewal&) = delete;
    Renewal& operator=(const Renewal&) = delete;

   private:
    LeaseHeartbeat& owner_;
  };
  [[nodiscard]] Renewal renew(int64_t attemptId, double lifetimeSeconds, const std::atomic<double>& progress,
                              std::atomic<bool>& abandon);

 private:
  void run();
  void disarm();

  SchedulerLink& link_;
  const std::chrono::milliseconds period_;
  std::mutex mutex_;
  std::condition_variable changed_;
  bool armed_ = false, beating_ = false, ending_ = false;
  int64_t attemptId_ = 0;
  std::chrono::steady_clock::time_point expires_;  // when the lease lapses unless renewed
  const std::atomic<double>* progress_ = nullptr;
  std::atomic<bool>* abandon_ = nullptr;
  std::thread thread_;  // last: starts once the members it reads exist
};

}  // namespace pathfarm::farm
