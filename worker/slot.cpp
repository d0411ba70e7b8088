#include "worker/slot.h"

#include <spdlog/spdlog.h>
#include <sys/resource.h>

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <stop_token>
#include <thread>
#include <type_traits>
#include <vector>

#include "image/plane_memory.h"
#include "worker/backoff.h"
#include "worker/failure_class.h"
#include "worker/lease_heartbeat.h"
#include "worker/peak_memory.h"
#include "worker/scratch_file.h"
#include "worker/task_log.h"

namespace pathfarm::farm {
namespace {

using Clock = std::chrono::steady_clock;

// Long-poll length; a stop request cancels a poll under way.
constexpr double kLeaseWaitSeconds = 2;
// After a stop request, how long a finished result is still offered to an unreachable scheduler.
constexpr auto kDeliveryGrace = std::chrono::seconds(60);
// How often an output the scheduler could not take (DATA_LOSS: damaged on the way, or its
// disk failing) is sent before the attempt fails with the scheduler's reason.
constexpr int kUploadTries = 5;
// Follow-up tiles go to the scheduler in batches of at most this many, or this many bytes
// (a tile's pixel mask is a byte per pixel), far below gRPC's message limit.
constexpr int kFollowUpsPerBatch = 1024;
constexpr size_t kFollowUpBatchBytes = 1 << 20;

// The scheduler is out of reach: waiting is right, since it is nobody's fault.
bool isUnreachable(const grpc::Status& status) {
  return status.error_code() == grpc::StatusCode::UNAVAILABLE ||
         status.error_code() == grpc::StatusCode::DEADLINE_EXCEEDED;
}

bool isTransient(const grpc::Status& status) {
  return status.error_code() == grpc::StatusCode::UNAVAILABLE ||
         status.error_code() == grpc::StatusCode::DEADLINE_EXCEEDED ||
         status.error_code() == grpc::StatusCode::DATA_LOSS;
}

// CPU seconds this process has used, all threads. A task's core-seconds are the difference
// across it: exact for a worker with one slot, shared among concurrent tasks with more.
double processCpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const auto seconds = [](const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec); };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

// While a task runs: a stop request (SIGTERM, as a preempted node or a busy workstation
// gets) that the task outlasts by `grace` abandons it at its next check and marks it to be
// handed back, so that the scheduler gives it to another worker at once instead of
// waiting out its lease on a worker that is about to be killed. A task already abandoned
// (its lease lost) is left as it is.
class StopHandsBack {
 public:
  StopHandsBack(const std::atomic<bool>& stop, std::chrono::milliseconds grace, std::atomic<bool>& abandon,
                std::atomic<bool>& handedBack)
      : watch_([&stop, grace, &abandon, &handedBack](const std::stop_token& taskOver) {
          std::mutex mutex;
          std::condition_variable_any wake;
          std::unique_lock lock(mutex);
          std::optional<Clock::time_point> stopSeen;
          while (!taskOver.stop_requested()) {
            if (stop && !stopSeen) stopSeen = Clock::now();
            if (stopSeen && Clock::now() - *stopSeen >= grace) {
              if (!abandon.exchange(true)) handedBack = true;
              return;
            }
            // `stop` is set by a signal handler, which cannot notify: it is looked at every
            // 50 ms. The end of the task wakes the wait at once (a task of a few
            // milliseconds must not wait for the watch).
            wake.wait_for(lock, taskOver, std::chrono::milliseconds(50), [] { return false; });
          }
        }) {}

 private:
  std::jthread watch_;
};

class Slot {
 public:
  Slot(SchedulerLink& link, TaskRunner& runner, ChunkStore& cache, CacheBound& bound, const WorkerOptions& options,
       double heartbeatSeconds)
      : link_(link), runner_(runner), cache_(cache), bound_(bound), options_(options),
        heartbeat_(link, std::chrono::milliseconds(static_cast<int64_t>(heartbeatSeconds * 1000))) {}

  void run(const std::atomic<bool>& stop) {
    Backoff backoff = link_.backoff();
    while (!stop) {
      LeaseReply reply;
      WorkerSession session;
      const grpc::Status status = link_.lease(kLeaseWaitSeconds, reply, session);
      if (status.error_code() == grpc::StatusCode::UNAUTHENTICATED) {
        // A scheduler with a fresh database forgot our session.
        if (!link_.registerAgain(session, options_.name, options_.slots, options_.tags).ok()) backoff.sleep();
        continue;
      }
      if (stop) break;
      if (!status.ok()) {
        spdlog::warn("cannot lease a task: {}", status.error_message());
        backoff.sleep();
        continue;
      }
      backoff.reset();
      if (reply.has_task()) execute(reply.lease(), stop);
    }
  }

 private:
  // What a task read: input chunks, their bytes, and how many came from the cache.
  struct InputCount {
    std::atomic<int> chunks{0}, cached{0};
    std::atomic<int64_t> bytes{0};
  };

  // An input chunk from the cache or the scheduler.
  std::string fetch(const ChunkRef& ref, const std::atomic<bool>& abandon, InputCount& count) {
    ++count.chunks;
    if (auto bytes = cache_.get(ref.sha256())) {
      ++count.cached;
      count.bytes += static_cast<int64_t>(bytes->size());
      return *bytes;
    }
    std::string bytes;
    fromScheduler(ref, abandon, [&] { return link_.getChunk(ref.sha256(), bytes); });
    count.bytes += static_cast<int64_t>(bytes.size());
    cache_.put(bytes, ref);
    bound_.maybeTrim();
    return bytes;
  }

  // An input chunk as a verified file of the cache, streamed into it from the scheduler
  // unless it is there: a tile an assembly reads in place, never holding it whole.
  std::filesystem::path fetchFile(const ChunkRef& ref, const std::atomic<bool>& abandon, InputCount& count) {
    ++count.chunks;
    if (!isSha256Hex(ref.sha256())) throw TransferFailed("an input chunk is not named by a SHA-256 digest");
    const std::filesystem::path file = cache_.pathOf(ref.sha256());
    if (const auto size = cache_.verifiedSize(ref.sha256())) {
      ++count.cached;
      count.bytes += *size;
      // Touched, so the cache's trim (oldest first, nothing younger than minutes) leaves
      // it while the task reads it.
      std::error_code ignored;
      std::filesystem::last_write_time(file, std::filesystem::file_time_type::clock::now(), ignored);
      return file;
    }
    fromScheduler(ref, abandon, [&] { return link_.getChunkInto(ref.sha256(), cache_); });
    count.bytes += ref.size();
    bound_.maybeTrim();
    return file;
  }

  // Calls `get` until the scheduler hands out the chunk. An unreachable scheduler is
  // waited for (it is not the task's fault) until the lease is lost.
  template <class Get>
  void fromScheduler(const ChunkRef& ref, const std::atomic<bool>& abandon, Get get) {
    Backoff backoff = link_.backoff();
    for (;;) {
      const grpc::Status status = get();
      if (status.ok()) return;
      if (abandon) throw TaskAbandoned();
      if (!isTransient(status))
        throw TransferFailed("cannot fetch input chunk " + ref.sha256() + ": " + status.error_message());
      backoff.sleep();
    }
  }

  // The lease with its inputs: those it names or, leased without them
  // (Lease::inputs_streamed), those the scheduler streams. An unreachable scheduler is
  // waited for until the lease is lost.
  Lease withInputs(const Lease& lease, const std::atomic<bool>& abandon) {
    if (!lease.inputs_streamed()) return lease;
    Backoff backoff = link_.backoff();
    for (;;) {
      Lease full = lease;
      const grpc::Status status = link_.leaseInputs(full);
      if (status.ok()) return full;
      if (abandon || status.error_code() == grpc::StatusCode::FAILED_PRECONDITION) throw TaskAbandoned();
      if (!isTransient(status)) throw TransferFailed("cannot read the task's inputs: " + status.error_message());
      backoff.sleep();
    }
  }

  void execute(const Lease& lease, const std::atomic<bool>& stop) {
    TaskLog log;  // what this slot and the task's thread say about the task, for the scheduler
    const TaskLog::Capture onSlot(log);
    spdlog::info("task {} ({}) of shot {}: started", lease.task_id(), TaskKind_Name(lease.kind()), lease.shot_id());
    std::atomic<double> progress{0};
    std::atomic<bool> abandon{false};
    InputCount inputs;
    const double cpuBefore = processCpuSeconds();
    // What earlier tasks freed beyond the planes kept for reuse goes back to the system:
    // else a large task's memory would stay with the worker, and with one slot the peak
    // measured below (the task's own) would start from it.
    returnFreedBeyondReuse();
    const bool measuresPeak = options_.slots == 1 && restartPeakResident();
    const auto started = Clock::now();
    TaskOutput output;
    std::atomic<bool> handedBack{false};
    try {
      const StopHandsBack onStop(
          stop, std::chrono::milliseconds(static_cast<int64_t>(options_.handBackAfterSeconds * 1000)), abandon,
          handedBack);
      output = whileHeartbeating(lease, progress, abandon, [&] {
        const TaskLog::Capture onRunner(log);
        return runner_.run(
            withInputs(lease, abandon), [&](const ChunkRef& ref) { return fetch(ref, abandon, inputs); }, progress,
            abandon, [&](const ChunkRef& ref) { return fetchFile(ref, abandon, inputs); });
      });
    } catch (const TaskAbandoned&) {
      if (handedBack) {
        spdlog::warn("task {}: the worker is stopping; handed back to the scheduler", lease.task_id());
        reportFailure(lease, FAILURE_RELEASED, "its worker was told to stop and handed it back", log, stop);
        return;
      }
      spdlog::warn("task {}: lease lost, result dropped", lease.task_id());
      return;
    } catch (const std::exception& e) {
      const FailureClass kind = classifyFailure(e);
      spdlog::error("task {} failed ({}): {}", lease.task_id(), FailureClass_Name(kind), e.what());
      reportFailure(lease, kind, e.what(), log, stop);
      return;
    }
    const std::optional<uint64_t> peak = measuresPeak ? peakResidentBytes() : std::nullopt;
    spdlog::info("task {}: ran {:.2f} s; read {} input chunk(s), {:.2f} MB ({} from the cache){}{}", lease.task_id(),
                 std::chrono::duration<double>(Clock::now() - started).count(), inputs.chunks.load(),
                 1e-6 * static_cast<double>(inputs.bytes.load()), inputs.cached.load(),
                 peak ? fmt::format("; peak resident {:.2f} GiB", static_cast<double>(*peak) / (1u << 30)) : "",
                 describe(output.metrics));
    deliver(lease, output, processCpuSeconds() - cpuBefore, log, stop);
  }

  // The task's figures for its log line: "; name value, ...".
  static std::string describe(const std::map<std::string, double>& metrics) {
    std::string text;
    for (const auto& [name, value] : metrics) text += (text.empty() ? "; " : ", ") + name + " " + fmt::format("{:g}", value);
    return text;
  }

  // Runs `work` and renews the lease while it runs; a lease the scheduler no longer keeps
  // sets `abandon`. Returns what `work` returns (or throws).
  template <class Work>
  std::invoke_result_t<Work> whileHeartbeating(const Lease& lease, const std::atomic<double>& progress,
                                               std::atomic<bool>& abandon, Work work) {
    const LeaseHeartbeat::Renewal renewal =
        heartbeat_.renew(lease.attempt_id(), lease.expires_in_seconds(), progress, abandon);
    return work();
  }

  // Sends the output: while the scheduler is out of reach, until the lease is lost (after
  // a stop request, for kDeliveryGrace); a chunk it could not take, kUploadTries times;
  // a refusal, once. Returns the last answer.
  grpc::Status upload(const TaskOutput& output, ChunkRef& stored, const std::atomic<bool>& abandon,
                      const std::atomic<bool>& stop) {
    Backoff backoff = link_.backoff();
    const auto since = Clock::now();
    for (int tries = 1;; ++tries) {
      const grpc::Status status = output.chunkFile ? link_.putChunkFile(output.chunkFile->path(), stored)
                                                   : link_.putChunk(output.chunk, stored);
      if (status.ok() || abandon) return status;
      const bool waitForScheduler = isUnreachable(status) && !(stop && Clock::now() - since > kDeliveryGrace);
      const bool sendAgain = status.error_code() == grpc::StatusCode::DATA_LOSS && tries < kUploadTries;
      if (!waitForScheduler && !sendAgain) return status;
      backoff.sleep();
    }
  }

  // Uploads the output, renewing the lease meanwhile, and completes the task; an output
  // that cannot be uploaded fails the attempt with the scheduler's reason.
  void deliver(const Lease& lease, const TaskOutput& output, double coreSeconds, const TaskLog& log,
               const std::atomic<bool>& stop) {
    CompleteRequest request;
    request.set_attempt_id(lease.attempt_id());
    request.set_core_seconds(coreSeconds);
    for (const auto& [name, value] : output.metrics) (*request.mutable_metrics())[name] = value;
    ChunkRef& stored = *request.mutable_output();
    if (lease.kind() != TASK_NOOP) {
      const std::atomic<double> uploaded{1.0};
      std::atomic<bool> abandon{false};
      const grpc::Status status =
          whileHeartbeating(lease, uploaded, abandon, [&] { return upload(output, stored, abandon, stop); });
      if (abandon) {
        spdlog::warn("task {}: lease lost during the upload, result dropped", lease.task_id());
        return;
      }
      if (!status.ok()) {
        const std::string reason = "cannot upload its output: " + status.error_message();
        spdlog::error("task {}: {}", lease.task_id(), reason);
        reportFailure(lease, FAILURE_TRANSPORT, reason, log, stop);
        return;
      }
      spdlog::info("task {}: output {} uploaded ({:.2f} MB)", lease.task_id(), stored.sha256().substr(0, 12),
                   1e-6 * static_cast<double>(stored.size()));
    }
    if (!sendFollowUps(lease, output.followUps, log, stop)) return;
    request.set_log_tail(log.tail());
    // The scheduler checks the output before it answers: for a large frame that takes
    // longer than a lease, so the lease is renewed until the answer comes.
    const std::atomic<double> delivered{1.0};
    std::atomic<bool> lost{false};
    if (whileHeartbeating(lease, delivered, lost,
                          [&] { return report([&](ReportReply& r) { return link_.complete(request, r); }, stop); }))
      spdlog::info("task {}: done", lease.task_id());
  }

  // Sends the task's follow-up tiles in bounded batches, renewing the lease meanwhile.
  // Tiles the scheduler refuses fail the attempt; returns whether all were taken.
  bool sendFollowUps(const Lease& lease, const std::vector<TaskParams>& followUps, const TaskLog& log,
                     const std::atomic<bool>& stop) {
    const std::atomic<double> done{1.0};
    std::atomic<bool> abandon{false};
    ReportReply refusal;
    const bool sent = whileHeartbeating(lease, done, abandon, [&] {
      FollowUpsRequest batch;
      batch.set_attempt_id(lease.attempt_id());
      size_t bytes = 0;
      for (size_t i = 0; i < followUps.size(); ++i) {
        *batch.add_follow_ups() = followUps[i];
        bytes += followUps[i].ByteSizeLong();
        const bool last = i + 1 == followUps.size();
        if (!last && batch.follow_ups_size() < kFollowUpsPerBatch && bytes < kFollowUpBatchBytes) continue;
        if (!report([&](ReportReply& r) { return link_.reportFollowUps(batch, r); }, stop, &refusal)) return false;
        batch.clear_follow_ups();
        bytes = 0;
      }
      return true;
    });
    if (!sent && !refusal.reason().empty())
      reportFailure(lease, FAILURE_WORKER_FAULT, "its follow-up tiles were refused: " + refusal.reason(), log, stop);
    return sent;
  }

  void reportFailure(const Lease& lease, FailureClass kind, const std::string& reason, const TaskLog& log,
                     const std::atomic<bool>& stop) {
    FailRequest request;
    request.set_attempt_id(lease.attempt_id());
    request.set_reason(reason);
    request.set_failure_class(kind);
    request.set_log_tail(log.tail());
    report([&](ReportReply& r) { return link_.fail(request, r); }, stop);
  }

  // Sends a report until the scheduler answers; true if it was accepted. The answer goes
  // to `answer` if given.
  template <class Call>
  bool report(Call call, const std::atomic<bool>& stop, ReportReply* answer = nullptr) {
    Backoff backoff = link_.backoff();
    const auto since = Clock::now();
    for (;;) {
      ReportReply reply;
      const grpc::Status status = call(reply);
      if (status.ok()) {
        if (!reply.accepted()) spdlog::warn("the scheduler refused the report: {}", reply.reason());
        if (answer) *answer = reply;
        return reply.accepted();
      }
      if (!isTransient(status) || (stop && Clock::now() - since > kDeliveryGrace)) {
        spdlog::error("cannot report to the scheduler: {}", status.error_message());
        return false;
      }
      backoff.sleep();
    }
  }

  SchedulerLink& link_;
  TaskRunner& runner_;
  ChunkStore& cache_;
  CacheBound& bound_;
  const WorkerOptions& options_;
  LeaseHeartbeat heartbeat_;
};

}  // namespace

void runSlot(SchedulerLink& link, TaskRunner& runner, ChunkStore& cache, CacheBound& bound, const WorkerOptions& options,
             double heartbeatSeconds, const std::atomic<bool>& stop) {
  Slot(link, runner, cache, bound, options, heartbeatSeconds).run(stop);
}

}  // namespace pathfarm::farm
