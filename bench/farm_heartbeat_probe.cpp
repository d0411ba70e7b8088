// A heartbeat's round trip on a loaded farm: registers as a worker that leases nothing
// and sends a heartbeat (for an attempt it does not hold) every --period seconds, the
// same authenticated call and database transaction a busy worker's heartbeat makes.
// Runs until stdin closes or --seconds pass, then prints the latencies' median, 99th
// percentile and maximum, and how many calls failed.
//
//   build/bin/farm_heartbeat_probe --scheduler 127.0.0.1:PORT [--token-file F] [--period 0.05] [--seconds 600]
#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

#include "bench/command_line.h"
#include "proto/wire/connection.h"
#include "worker/scheduler_link.h"

namespace {

using Clock = std::chrono::steady_clock;

// Whether stdin was closed (the script's way of saying "stop"), waiting up to `seconds`.
bool stdinClosedWithin(double seconds) {
  pollfd in{STDIN_FILENO, POLLIN, 0};
  if (poll(&in, 1, static_cast<int>(seconds * 1000)) <= 0) return false;
  char byte;
  return read(STDIN_FILENO, &byte, 1) <= 0;
}

double quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  return values[static_cast<size_t>(q * static_cast<double>(values.size() - 1))];
}

}  // namespace

int main(int argc, char** argv) {
  pathfarm::bench::CommandLine app("heartbeat latency probe");
  std::string scheduler, tokenFile;
  double period = 0.05, seconds = 600;
  app.option("--scheduler", scheduler).required();
  app.option("--token-file", tokenFile);
  app.option("--period", period);
  app.option("--seconds", seconds);
  if (const auto exit = app.parse(argc, argv)) return *exit;

  using namespace pathfarm::farm;
  SchedulerLink link(scheduler, loadToken(tokenFile));
  RegisterReply registration;
  if (const grpc::Status status = link.registerWorker("heartbeat-probe", 1, {}, registration); !status.ok()) {
    std::fprintf(stderr, "probe: cannot register: %s\n", status.error_message().c_str());
    return 1;
  }
  std::vector<double> latencies;
  int failed = 0;
  const auto end = Clock::now() + std::chrono::duration<double>(seconds);
  while (Clock::now() < end) {
    const auto sent = Clock::now();
    HeartbeatReply reply;
    if (link.heartbeat(0, 0, reply).ok()) {
      latencies.push_back(std::chrono::duration<double>(Clock::now() - sent).count());
    } else {
      ++failed;
    }
    if (stdinClosedWithin(period)) break;
  }
  std::printf("heartbeats %zu, failed %d, latency median %.1f ms, p99 %.1f ms, max %.1f ms\n", latencies.size(),
              failed, 1e3 * quantile(latencies, 0.5), 1e3 * quantile(latencies, 0.99),
              1e3 * quantile(latencies, 1.0));
  return 0;
}
