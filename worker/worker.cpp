#include "worker/worker.h"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <chrono>
#include <thread>
#include <vector>

#include "proto/wire/chunk_store.h"
#include "proto/wire/connection.h"
#include "worker/backoff.h"
#include "worker/cache_trim.h"
#include "worker/scheduler_link.h"
#include "worker/scratch_file.h"
#include "worker/slot.h"
#include "worker/task_log.h"
#include "worker/task_runner.h"

namespace pathfarm::farm {
namespace {

std::string defaultName() {
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  return std::string(host) + ":" + std::to_string(getpid());
}

}  // namespace

Worker::Worker(WorkerOptions options) : options_(std::move(options)) {
  if (options_.name.empty()) options_.name = defaultName();
  if (options_.cache.empty()) options_.cache = std::filesystem::temp_directory_path() / "pathfarm-worker-cache";
}

void Worker::run(const std::atomic<bool>& stop) {
  installTaskLogSink();
  SchedulerLink link(options_.scheduler, options_.token, options_.tls);
  RegisterReply registration;
  Backoff backoff = link.backoff();
  for (;;) {
    const grpc::Status status = link.registerWorker(options_.name, options_.slots, options_.tags, registration);
    if (status.ok()) break;
    // A refusal (bad token, bad tag) or a refused certificate does not change by waiting.
    const auto code = status.error_code();
    if (code == grpc::StatusCode::UNAUTHENTICATED || code == grpc::StatusCode::INVALID_ARGUMENT ||
        code == grpc::StatusCode::PERMISSION_DENIED)
      throw std::runtime_error("the scheduler refused this worker: " + status.error_message());
    const bool overTls = options_.tls.enabled();
    if (connectionTrouble(status, overTls) == ConnectionTrouble::CertificateRefused)
      throw std::runtime_error("cannot connect to the scheduler at " + options_.scheduler + " over TLS: " +
                               explainedError(status, overTls));
    if (stop) return;
    spdlog::warn("cannot reach the scheduler at {}: {}; retrying", options_.scheduler, explainedError(status, overTls));
    backoff.sleep();
  }
  const int64_t workerId = registration.worker_id();
  spdlog::info("worker {} ({}) registered with {}: {} slots", workerId, options_.name, options_.scheduler,
               options_.slots);
  ChunkStore cache(options_.cache, ChunkStore::Kind::Cache);
  if (const size_t removed = cache.removeAbandonedWrites(); removed > 0)
    spdlog::info("removed {} chunk(s) left half-written in the cache by a worker that was killed", removed);
  CacheBound bound(options_.cache, options_.cacheMaxBytes);
  bound.maybeTrim();
  removeOrphanedScratchFiles(options_.cache / "outgoing");
  TaskRunner runner(options_.threads, options_.cache / "scenes", options_.cache / "outgoing",
                    options_.decodedInputMaxBytes);
  std::vector<std::thread> slots;
  for (int i = 0; i < options_.slots; ++i) {
    slots.emplace_back([&] {
      runSlot(link, runner, cache, bound, options_, registration.heartbeat_seconds(), stop);
    });
  }
  while (!stop) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  link.stopLeasing();
  for (std::thread& t : slots) t.join();
  spdlog::info("worker {} stopped", workerId);
}

}  // namespace pathfarm::farm
