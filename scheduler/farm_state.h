#pragma once
// Everything the farm knows, in SQLite, and every change to it as one transaction:
// shots and their task graphs, leases and attempts, workers, chunks and events. The
// rules for which task a worker gets next live in one place (lease()), and the timeouts
// in one checker (expireLeases()). Times are wall-clock seconds since the epoch, passed
// in by the caller so that tests control them.
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "pathfarm/client_service.pb.h"
#include "pathfarm/worker_service.pb.h"
#include "scheduler/farm_metrics.h"
#include "scheduler/planner.h"
#include "scheduler/sqlite_db.h"

namespace pathfarm::farm {

struct FarmSettings {
  double leaseSeconds = 30;        // a lease lives this long without a heartbeat
  double hungSeconds = 600;        // a task whose progress stalls this long is revoked
  double retryBackoffSeconds = 1;  // first retry delay; doubles per failure, capped
  double maxBackoffSeconds = 60;
  int blocklistAfter = 3;          // a worker failing this many tasks of a shot is blocklisted for
                                   // it; when no live worker is left, the shot fails
  int defaultMaxAttempts = 3;
  // A lease that expires (the worker vanished: killed, preempted, cut off) is not charged
  // to the task's max_attempts; a task whose workers vanish this often may be what kills
  // them, and fails the shot.
  int maxLostWorkers = 10;
  // A lease names at most this many inputs; a task with more (a composite waiting for the
  // re-render tiles of a large frame) is leased with none, and the worker reads them in
  // parts of at most kInputsPerPart (leaseInputs). Either way no message nears gRPC's limit.
  int64_t inlineLeaseInputs = 1024;
  // A shot finished this long ago is deleted with its tasks, attempts and events, and so
  // are chunks nothing kept refers to and stored as long ago; 0 keeps everything.
  double retainSeconds = 0;
  // Keeps every intermediate chunk until retention (for looking into a shot's stages)
  // instead of removing each once no task reads it.
  bool keepIntermediates = false;
};

// A task as the shot's report sees it.
struct TaskRecord {
  TaskKind kind = TASK_KIND_UNSPECIFIED;
  TaskParams params;
  bool done = false;
  double coreSeconds = 0;  // of the accepted attempt
  std::map<std::string, double> metrics;
  std::string outputSha;  // the output chunk of a done task
};

// Done, failed or cancelled: nothing more will run for the shot.
inline bool isFinished(ShotState state) {
  return state == SHOT_DONE || state == SHOT_FAILED || state == SHOT_CANCELLED;
}

class FarmState {
 public:
  // Opens (and migrates) the database. Leases still running from a previous scheduler
  // get one more lease period, so their workers can reconnect and deliver.
  FarmState(const std::string& databaseFile, FarmSettings settings, double now);

  // A shot and its tasks; with a `submitKey` that an earlier submit carried, nothing is
  // added and that submit's shot is returned (a client retrying a submit it did not hear
  // back from makes one shot, not two).
  // Tasks go in kTasksPerTransaction at a time (farm_state_submit.cpp).
  int64_t submit(const ShotSpec& spec, const std::vector<PlannedTask>& plan, double now,
                 const std::string& submitKey = "");
  static constexpr size_t kTasksPerTransaction = 2000;
  // `sessionHash`: the SHA-256 hex of the key the worker proves itself with from now on.
  int64_t registerWorker(const std::string& name, int slots, double now, const std::vector<std::string>& tags = {},
                         const std::string& sessionHash = "");
  // Whether the worker registered with this session key's hash (farm_state_sessions.cpp).
  bool sessionMatches(int64_t workerId, const std::string& sessionHash);
  // The worker an attempt was leased to; nothing for an unknown attempt.
  std::optional<int64_t> attemptWorker(int64_t attemptId);
  // The task of a running attempt and its shot's spec, to check an output against;
  // nothing for an attempt that is not running.
  struct AttemptTask {
    TaskKind kind = TASK_KIND_UNSPECIFIED;
    TaskParams params;
    ShotSpec spec;
  };
  std::optional<AttemptTask> runningAttemptTask(int64_t attemptId);

  // The next task for this worker, or nothing: ready tasks of running or queued shots
  // the worker is not blocklisted for, by shot priority (high first), then shot age,
  // then task order; tasks in retry backoff wait.
  std::optional<Lease> lease(int64_t workerId, double now);
  // A running attempt's inputs in task order, after the input the task `afterTaskId` made
  // (0: from the first), at most kInputsPerPart of them; nothing for an attempt that is not
  // running (farm_state_follow_ups.cpp).
  struct InputsPart {
    LeaseInputsPart part;
    int64_t lastTaskId = 0;  // the `afterTaskId` of the next part; 0 when none was left
  };
  std::optional<InputsPart> leaseInputs(int64_t attemptId, int64_t afterTaskId);
  static constexpr int64_t kInputsPerPart = 1024;
  HeartbeatReply heartbeat(int64_t attemptId, double progress, double now);
  // Render tiles a running attempt asks for (pixels its filter flagged), kept until it
  // completes, when they join the shot, or ends otherwise, when they are dropped. A batch
  // is refused whole for an attempt that is not running, a tile outside its frame or
  // larger than the shot's tiles, or more tiles in all than one frame holds
  // (farm_state_follow_ups.cpp).
  ReportReply stageFollowUps(int64_t attemptId, const google::protobuf::RepeatedPtrField<TaskParams>& followUps);
  // Accepts the output and the task's figures; its staged follow-up tiles join the shot.
  ReportReply complete(const CompleteRequest& request, double now);
  // `logTail`: what the worker logged while it ran the attempt (kept to kMaxLogTailBytes).
  // A worker fault runs the task again and counts toward the worker's blocklist; a
  // transport failure runs it again and blames no one; bad input, once a second worker
  // reports it too, fails the task and its shot, since no worker could run it.
  ReportReply fail(int64_t attemptId, const std::string& reason, double now, const std::string& logTail = "",
                   FailureClass kind = FAILURE_WORKER_FAULT);
  static constexpr size_t kMaxLogTailBytes = 16384;
  // Expired leases and hung tasks go back to the queue (or fail their shot when out of
  // attempts). Returns how many leases ended.
  int expireLeases(double now);
  // Deletes shots finished more than settings().retainSeconds ago and the chunk rows that
  // neither a kept task's output nor a kept shot's input names (and stored as long ago:
  // a chunk uploaded for a shot about to be submitted stays). Returns the chunks whose
  // files may go (farm_state_retention.cpp).
  struct Collected {
    std::vector<int64_t> shots;
    std::vector<std::string> chunks;
  };
  Collected collectGarbage(double now);
  // The files of intermediate chunks that no task reads any more, to be removed from the
  // store (unless settings().keepIntermediates): a render tile once its frame is
  // assembled, a keyframe once it is filtered, and so on; never a shot's frames or its
  // references (docs/farm.md, "Retention"). Their rows stay, marked released, so a chunk
  // needed again (its reader requeued) is made again by requeueProducersOf. Each once.
  std::vector<std::string> takeReleasedChunks();
  // Every chunk marked released: a scheduler killed between committing a release and
  // removing the files left them in the store, so it looks for them when it starts.
  std::vector<std::string> releasedChunks();

  void recordChunk(const ChunkRef& chunk, double now);
  bool hasChunk(const std::string& sha256);

  // Throw std::out_of_range for an unknown shot.
  ShotSummary summary(int64_t shotId, double now);
  ShotReply shot(int64_t shotId, double now);
  std::vector<ShotSummary> shots(double now);
  ShotSummary cancel(int64_t shotId, double now);
  ShotSummary pause(int64_t shotId, double now);
  ShotSummary resume(int64_t shotId, double now);
  // A FAILED shot runs again: its failed tasks are ready with fresh counts, its
  // blocklist is cleared, and everything done stays done. Other shots are left as they are.
  ShotSummary retry(int64_t shotId, double now);
  ShotSummary setPriority(int64_t shotId, int priority, double now);
  // The task runs again (a running attempt is revoked), and so does every task that used
  // its output, directly or not; re-render tiles those tasks asked for are dropped, to be
  // asked for again. A done shot becomes active again; a failed shot (retry it first), a
  // cancelled one, a task of another shot or an unknown task is refused with
  // std::invalid_argument, an unknown shot with std::out_of_range (farm_state_requeue.cpp).
  ShotSummary requeueTask(int64_t shotId, int64_t taskId, double now);
  // The same for every task of one frame: its tiles, filters and output.
  ShotSummary requeueFrame(int64_t shotId, int64_t frame, double now);
  // A chunk the store has lost (missing or damaged on disk): every done task that made it,
  // in a shot still queued, running, paused or done, runs again with what used it. Returns
  // how many tasks were requeued (0: no task can make it again).
  // A released chunk (takeReleasedChunks) is made again only while a task that reads it
  // waits: a late worker fetching it for an attempt already redone elsewhere changes nothing.
  int requeueProducersOf(const std::string& sha256, double now);
  // Blocklisted workers of one shot, or of every shot with 0.
  std::vector<BlocklistEntry> blocklist(int64_t shotId);
  // Lifts the blocklist of `workerId` (0: every worker) for the shot.
  void clearBlocklist(int64_t shotId, int64_t workerId, double now);
  // The frames a shot has produced: (frame, chunk) in frame order.
  std::vector<std::pair<int64_t, ChunkRef>> outputs(int64_t shotId);
  // Its reference frames, rendered or given: (frame, chunk) in task order.
  std::vector<std::pair<int64_t, ChunkRef>> references(int64_t shotId);
  std::vector<WorkerInfo> workers(double now);
  // The shot's spec and every task's figures, for its report. Throws std::out_of_range.
  std::pair<ShotSpec, std::vector<TaskRecord>> taskRecords(int64_t shotId);
  // The figures /metrics serves (farm_state_metrics.cpp); the chunk traffic is the
  // store's, filled in by the caller.
  FarmMetrics metrics(double now);

  const FarmSettings& settings() const { return settings_; }

  // The dashboard's reads (farm_state_dashboard.cpp): what the tasks and attempts tables
  // hold, as they are, for people to look at.
  struct AttemptDetail {
    int64_t id = 0;
    int64_t workerId = 0;
    std::string workerName;
    int state = 0;  // an AttemptState
    double leasedAt = 0;
    std::optional<double> finishedAt;
    double progress = 0;
    std::string error;
    std::string failureClass;  // of a failed attempt: "worker_fault", "bad_input" or "transport"
    std::string logTail;  // the worker's log lines of the attempt, as it sent them
  };
  struct TaskDetail {
    int64_t id = 0;
    TaskKind kind = TASK_KIND_UNSPECIFIED;
    TaskParams params;
    int state = 0;  // a TaskState
    int64_t failures = 0, lost = 0, maxAttempts = 0;
    double coreSeconds = 0;
    std::vector<AttemptDetail> attempts;  // oldest first
  };
  struct TaskPage {
    int64_t matching = 0;  // tasks passing the filter, of which `tasks` is a slice
    std::vector<TaskDetail> tasks;
  };
  // A shot's tasks in task order, only those in `state` (a TaskState) if given, `limit`
  // from `offset`. Throws std::out_of_range for an unknown shot.
  TaskPage taskDetails(int64_t shotId, std::optional<int> state, int64_t offset, int64_t limit);
  struct RunningTask {
    int64_t workerId = 0, shotId = 0, taskId = 0, attemptId = 0;
    TaskKind kind = TASK_KIND_UNSPECIFIED;
    int64_t frame = 0;
    double leasedAt = 0, progress = 0;
  };
  // Every attempt running now, by worker.
  std::vector<RunningTask> runningTasks();

 private:
  struct AttemptRow;
  // Runs `body` as one transaction under the lock; commits when it returns normally and
  // rolls back when it throws.
  template <class Body>
  auto transact(Body body) -> decltype(body());
  std::optional<AttemptRow> currentAttempt(int64_t attemptId);
  void endAttempt(const AttemptRow& attempt, int state, const std::string& error, double now,
                  const std::string& logTail = "", const std::string& failureClass = "");
  void retryOrFail(const AttemptRow& attempt, const std::string& reason, bool blameWorker, double now);
  bool anotherWorkerFoundBadInput(const AttemptRow& attempt);
  void failOnBadInput(const AttemptRow& attempt, const std::string& reason, double now);
  void retryLost(const AttemptRow& attempt, const std::string& reason, double now);
  // The task failed for good, and its shot with `why`; `counter` (failures or lost) is
  // recorded as `count`.
  void failTask(const AttemptRow& attempt, const char* counter, int count, const std::string& why, double now);
  // The task is ready again from `notBefore`, with `counter` recorded as `count`.
  void retryLater(const AttemptRow& attempt, const char* counter, int count, double notBefore);
  int64_t insertTask(int64_t shotId, TaskKind kind, const TaskParams& params, size_t dependencies,
                     int64_t maxAttempts, bool output);
  // The attempt's staged follow-ups become render tiles of its shot, and every composite
  // task waiting for the attempt's task waits for them too.
  void addFollowUps(const AttemptRow& attempt, double now);
  // Staged follow-ups of attempts no longer running are dropped.
  void dropStaleFollowUps();
  int64_t inputCount(int64_t taskId);
  // Done tasks of the shot matching the SQL `condition` (over tasks as t) whose params
  // `keep` accepts: (frame, output chunk) in task order.
  std::vector<std::pair<int64_t, ChunkRef>> doneFrames(int64_t shotId, const std::string& condition,
                                                       const std::function<bool(const TaskParams&)>& keep);
  // Adds the task's inputs after `afterTaskId`, at most `limit`, to a Lease or a
  // LeaseInputsPart; returns the last one's task id (0: none).
  template <class Message>
  int64_t appendInputs(int64_t taskId, int64_t afterTaskId, int64_t limit, Message& message);
  void countTaskDone(int64_t shotId, double now);
  bool anyWorkerCanRun(int64_t shotId, double now);
  void endShot(int64_t shotId, ShotState state, const std::string& failure, double now);
  // Fails the unfinished shots waiting for `shotId`, which ended failed or cancelled.
  void failShotsWaitingFor(int64_t shotId, ShotState state, double now);
  // Throws std::invalid_argument unless every shot `spec` waits for exists and can still be done.
  void checkShotsWaitedFor(const ShotSpec& spec);
  void setShotState(int64_t shotId, ShotState state, double now);
  // Queued or running again, as far as it had got.
  void reactivate(int64_t shotId, double now);
  // Runs `seeds` and everything downstream of them again (farm_state_requeue.cpp).
  ShotSummary requeueLocked(int64_t shotId, const std::vector<int64_t>& seeds, const std::string& what, double now);
  // One transaction: `change` gets the shot's state; the summary after is returned.
  template <class Change>
  ShotSummary changeShot(int64_t shotId, double now, Change change);
  void addEvent(int64_t shotId, const std::string& message, double now);
  ShotSummary summaryLocked(int64_t shotId, double now);
  FarmMetrics metricsLocked(double now);
  std::optional<int64_t> nextTask(int64_t workerId, double now);
  // The pool rules: the worker carries the shot's required tags and its cap allows it.
  bool workerMayJoin(int64_t workerId, int64_t shotId);

  // Marks released, and returns, the outputs of `taskId`'s dependencies that no task
  // waits for any more and that are neither a shot's frame nor a reference.
  std::vector<std::string> releaseConsumedInputs(int64_t taskId);

  std::mutex mutex_;  // one writer: every public method is one transaction under it
  Database db_;
  FarmSettings settings_;
  std::mutex releasedMutex_;
  std::vector<std::string> releasedChunks_;  // committed, their files not yet removed
};

}  // namespace pathfarm::farm
