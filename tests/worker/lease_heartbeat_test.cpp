// The lease heartbeat when its scheduler is out of reach: a lease left unrenewed past its
// lifetime is abandoned (the scheduler requeues it once it runs again), and not before.
#include "worker/lease_heartbeat.h"

#include <gtest/gtest.h>

#include <thread>

namespace pathfarm::farm {
namespace {

using namespace std::chrono_literals;

// Nothing listens on port 1 of the loopback: every renewal fails at once.
constexpr const char* kNobody = "127.0.0.1:1";

TEST(LeaseHeartbeat, ALeaseUnrenewedPastItsLifetimeIsAbandoned) {
  SchedulerLink link(kNobody, "");
  LeaseHeartbeat heartbeat(link, 50ms);
  const std::atomic<double> progress{0.5};
  std::atomic<bool> abandon{false};
  const auto start = std::chrono::steady_clock::now();
  {
    const LeaseHeartbeat::Renewal renewal = heartbeat.renew(7, 0.3, progress, abandon);
    while (!abandon && std::chrono::steady_clock::now() - start < 10s) std::this_thread::sleep_for(10ms);
  }
  EXPECT_TRUE(abandon);
  EXPECT_GE(std::chrono::steady_clock::now() - start, 300ms);
}

TEST(LeaseHeartbeat, ALeaseWithinItsLifetimeIsKeptThroughFailedRenewals) {
  SchedulerLink link(kNobody, "");
  LeaseHeartbeat heartbeat(link, 50ms);
  const std::atomic<double> progress{0.5};
  std::atomic<bool> abandon{false};
  {
    const LeaseHeartbeat::Renewal renewal = heartbeat.renew(8, 60, progress, abandon);
    std::this_thread::sleep_for(500ms);  // about ten failed renewals
  }
  EXPECT_FALSE(abandon);
}

}  // namespace
}  // namespace pathfarm::farm
