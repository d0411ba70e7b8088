#include "worker/lease_heartbeat.h"

#include <spdlog/spdlog.h>

namespace pathfarm::farm {

LeaseHeartbeat::LeaseHeartbeat(SchedulerLink& link, std::chrono::milliseconds period)
    : link_(link), period_(period), thread_([this] { run(); }) {}

LeaseHeartbeat::~LeaseHeartbeat() {
  {
    const std::lock_guard lock(mutex_);
    ending_ = true;
  }
  changed_.notify_all();
  thread_.join();
}

namespace {

std::chrono::steady_clock::time_point after(double seconds) {
  return std::chrono::steady_clock::now() +
         std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(seconds));
}

}  // namespace

LeaseHeartbeat::Renewal LeaseHeartbeat::renew(int64_t attemptId, double lifetimeSeconds,
                                              const std::atomic<double>& progress, std::atomic<bool>& abandon) {
  {
    const std::lock_guard lock(mutex_);
    armed_ = true;
    attemptId_ = attemptId;
    expires_ = after(lifetimeSeconds);
    progress_ = &progress;
    abandon_ = &abandon;
  }
  changed_.notify_all();
  return Renewal(*this);
}

void LeaseHeartbeat::disarm() {
  std::unique_lock lock(mutex_);
  armed_ = false;
  changed_.wait(lock, [&] { return !beating_; });
  progress_ = nullptr;
  abandon_ = nullptr;
  changed_.notify_all();
}

void LeaseHeartbeat::run() {
  std::unique_lock lock(mutex_);
  while (!ending_) {
    changed_.wait(lock, [&] { return armed_ || ending_; });
    // A full period after arming, as the thread per task did: a task shorter than the
    // period sends no heartbeat at all.
    const int64_t attempt = attemptId_;
    if (changed_.wait_for(lock, period_, [&] { return !armed_ || ending_ || attemptId_ != attempt; })) continue;
    beating_ = true;
    const double progress = *progress_;
    lock.unlock();
    HeartbeatReply beat;
    const grpc::Status status = link_.heartbeat(attempt, progress, beat);
    lock.lock();
    if (status.ok() && beat.keep_going()) {
      expires_ = after(beat.expires_in_seconds());
    } else if (status.ok() || std::chrono::steady_clock::now() > expires_) {
      if (!status.ok())
        spdlog::warn("attempt {}: the lease lapsed while the scheduler was out of reach ({}); the task stops",
                     attempt, status.error_message());
      *abandon_ = true;
    }
    beating_ = false;
    changed_.notify_all();
  }
}

}  // namespace pathfarm::farm
