#pragma once
// `pathfarm worker`: a stateless process that registers with the scheduler, then in each
// of its slots leases a task, runs it (renewing the lease with heartbeats), and delivers
// the output chunk. Nothing it holds matters if it dies: the lease expires and another
// worker redoes the task. A finished result it cannot deliver (scheduler down) is kept
// and retried with backoff, so a scheduler restart costs no finished work.
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "proto/wire/tls.h"
#include "worker/task_runner.h"

namespace pathfarm::farm {

struct WorkerOptions {
  std::string scheduler = "127.0.0.1:7700";
  int slots = 1;    // tasks run at once
  int threads = 0;  // render threads per task; 0: every core
  std::string name;
  std::string token;
  std::filesystem::path cache;  // input chunks and uploaded scenes; default: a folder under the temp dir
  uint64_t cacheMaxBytes = 20'000'000'000;  // the cache is trimmed to this, oldest first
  uint64_t decodedInputMaxBytes = TaskRunner::kDefaultDecodedInputBytes;  // input frames kept decoded (decoded_inputs.h)
  std::vector<std::string> tags;  // the pools this worker serves (shots' required_tags)
  ClientTls tls;  // a CA names: the scheduler is reached over TLS
  // After a stop request, a task still running this long is abandoned and handed back to
  // the scheduler (a preempted node's notice is short); one that ends sooner is delivered.
  double handBackAfterSeconds = 20;
};

class Worker {
 public:
  explicit Worker(WorkerOptions options);
  // Works until `stop` turns true, then finishes and delivers the tasks in hand (handing
  // back those that outlast handBackAfterSeconds) and returns. Throws std::runtime_error if the scheduler refuses the worker (bad token).
  void run(const std::atomic<bool>& stop);

 private:
  WorkerOptions options_;
};

}  // namespace pathfarm::farm
