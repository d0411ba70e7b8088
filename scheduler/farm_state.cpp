#include "scheduler/farm_state.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "scheduler/farm_names.h"
#include "scheduler/farm_state_internal.h"
#include "scheduler/quoted_text.h"
#include "scheduler/schema.h"

namespace pathfarm::farm {

namespace {

bool carriesEveryTag(const std::string& offered, const std::string& required) {
  size_t start = 1;
  while (start < required.size()) {
    const size_t end = required.find(',', start);
    if (offered.find(required.substr(start - 1, end - start + 2)) == std::string::npos) return false;
    start = end + 1;
  }
  return true;
}

}  // namespace

FarmState::FarmState(const std::string& databaseFile, FarmSettings settings, double now)
    : db_(databaseFile), settings_(settings) {
  migrate(db_);
  Transaction transaction(db_);
  // A shot still building lost its submit with the scheduler before (farm_state_submit.cpp).
  db_.execute("DELETE FROM shots WHERE building = 1");
  db_.query("UPDATE attempts SET expires_at = MAX(expires_at, ?1), progress_at = MAX(progress_at, ?2) WHERE state = ?3")
      .bind(1, now + settings_.leaseSeconds)
      .bind(2, now)
      .bind(3, int64_t{kRunning})
      .run();
  transaction.commit();
}

int64_t FarmState::registerWorker(const std::string& name, int slots, double now,
                                  const std::vector<std::string>& tags, const std::string& sessionHash) {
  return transact([&]() -> int64_t {
    db_.query("INSERT INTO workers (name, slots, registered_at, last_seen, tags, session_hash) "
              "VALUES (?1, ?2, ?3, ?3, ?4, ?5)")
        .bind(1, name)
        .bind(2, int64_t{slots})
        .bind(3, now)
        .bind(4, tagList(tags.begin(), tags.end()))
        .bind(5, sessionHash)
        .run();
    const int64_t id = db_.lastInsertId();
    // A worker registering again under its name (its session lost, or restarted with the
    // same --name) keeps its failures and blocklist: registering is no way out of them.
    db_.query("INSERT OR IGNORE INTO worker_failures (shot_id, worker_id, failures, blocklisted) "
              "SELECT shot_id, ?1, MAX(failures), MAX(blocklisted) FROM worker_failures WHERE worker_id IN "
              "(SELECT id FROM workers WHERE name = ?2 AND id != ?1) GROUP BY shot_id")
        .bind(1, id)
        .bind(2, name)
        .run();
    return id;
  });
}

std::optional<int64_t> FarmState::nextTask(int64_t workerId, double now) {
  // Rule order: active shots only; not blocklisted for this worker; the worker carries
  // every tag the shot requires; the shot's cap on workers is not reached (or this worker
  // is already one of them); priority, then age.
  std::vector<int64_t> shots;
  Statement& shotQuery = db_.query(
      "SELECT id, required_tags != '' OR max_workers > 0 FROM shots WHERE state IN (?1, ?2) AND building = 0 "
      "AND id NOT IN "
      "(SELECT shot_id FROM worker_failures WHERE worker_id = ?3 AND blocklisted = 1) "
      "AND NOT EXISTS (SELECT 1 FROM shot_waits w JOIN shots p ON p.id = w.after_id "
      "WHERE w.shot_id = shots.id AND p.state != ?4) "
      "ORDER BY priority DESC, id ASC");
  shotQuery.bind(1, int64_t{SHOT_QUEUED}).bind(2, int64_t{SHOT_RUNNING}).bind(3, workerId).bind(4, int64_t{SHOT_DONE});
  while (shotQuery.step()) {
    const int64_t shot = shotQuery.integer(0);
    // The pool rules are read only for shots that have any: a farm without pools pays nothing.
    if (shotQuery.integer(1) == 0 || workerMayJoin(workerId, shot)) shots.push_back(shot);
  }
  // Then: a ready task, not in retry backoff, in the order the planner made them.
  for (const int64_t shot : shots) {
    Statement& taskQuery = db_.query(
        "SELECT id FROM tasks WHERE shot_id = ?1 AND state = ?2 AND not_before <= ?3 ORDER BY id LIMIT 1");
    taskQuery.bind(1, shot).bind(2, asInt(TaskState::Ready)).bind(3, now);
    if (taskQuery.step()) {
      const int64_t task = taskQuery.integer(0);
      taskQuery.reset();
      return task;
    }
  }
  return std::nullopt;
}

bool FarmState::workerMayJoin(int64_t workerId, int64_t shotId) {
  Statement& q = db_.query(
      "SELECT s.required_tags, w.tags, s.max_workers, (SELECT COUNT(DISTINCT a.worker_id) FROM attempts a "
      "JOIN tasks t ON t.id = a.task_id WHERE t.shot_id = s.id AND a.state = ?3 AND a.worker_id != w.id) "
      "FROM shots s, workers w WHERE s.id = ?1 AND w.id = ?2");
  q.bind(1, shotId).bind(2, workerId).bind(3, int64_t{kRunning});
  if (!q.step()) return false;
  const bool tagged = carriesEveryTag(q.text(1), q.text(0));
  const int64_t cap = q.integer(2), others = q.integer(3);
  q.reset();
  return tagged && (cap == 0 || others < cap);
}

std::optional<Lease> FarmState::lease(int64_t workerId, double now) {
  return transact([&]() -> std::optional<Lease> {
    // Asking for work is a sign of life, whether or not there is any.
    db_.query("UPDATE workers SET last_seen = ?1 WHERE id = ?2").bind(1, now).bind(2, workerId).run();
    const auto taskId = nextTask(workerId, now);
    if (!taskId) return std::nullopt;

    db_.query("INSERT INTO attempts (task_id, worker_id, state, leased_at, expires_at, progress_at) "
              "VALUES (?1, ?2, ?3, ?4, ?5, ?4)")
        .bind(1, *taskId)
        .bind(2, workerId)
        .bind(3, int64_t{kRunning})
        .bind(4, now)
        .bind(5, now + settings_.leaseSeconds)
        .run();
    const int64_t attemptId = db_.lastInsertId();
    db_.query("UPDATE tasks SET state = ?1, attempt_id = ?2 WHERE id = ?3")
        .bind(1, asInt(TaskState::Leased))
        .bind(2, attemptId)
        .bind(3, *taskId)
        .run();

    Lease lease;
    lease.set_attempt_id(attemptId);
    lease.set_task_id(*taskId);
    lease.set_expires_in_seconds(settings_.leaseSeconds);
    {
      Statement& q = db_.query(
          "SELECT t.shot_id, t.kind, t.params, s.spec, s.state FROM tasks t JOIN shots s ON s.id = t.shot_id "
          "WHERE t.id = ?1");
      q.bind(1, *taskId);
      q.step();
      lease.set_shot_id(q.integer(0));
      lease.set_kind(static_cast<TaskKind>(q.integer(1)));
      lease.mutable_params()->ParseFromString(q.blob(2));
      lease.mutable_spec()->ParseFromString(q.blob(3));
      const auto shotState = static_cast<ShotState>(q.integer(4));
      q.reset();
      if (shotState == SHOT_QUEUED) {
        db_.query("UPDATE shots SET state = ?1, started_at = ?2 WHERE id = ?3")
            .bind(1, int64_t{SHOT_RUNNING})
            .bind(2, now)
            .bind(3, lease.shot_id())
            .run();
        addEvent(lease.shot_id(), "started", now);
      }
    }
    // However many inputs a task has, no message is near gRPC's limit: above
    // inlineLeaseInputs, the worker reads them in parts (leaseInputs).
    if (inputCount(*taskId) > settings_.inlineLeaseInputs) {
      lease.set_inputs_streamed(true);
    } else {
      appendInputs(*taskId, 0, settings_.inlineLeaseInputs, lease);
    }
    return lease;
  });
}

std::optional<FarmState::AttemptRow> FarmState::currentAttempt(int64_t attemptId) {
  Statement& q = db_.query(
      "SELECT a.id, a.task_id, t.shot_id, a.worker_id, t.kind, t.failures, t.max_attempts, t.params, t.lost "
      "FROM attempts a JOIN tasks t ON t.id = a.task_id "
      "WHERE a.id = ?1 AND a.state = ?2 AND t.attempt_id = a.id AND t.state = ?3");
  q.bind(1, attemptId).bind(2, int64_t{kRunning}).bind(3, asInt(TaskState::Leased));
  if (!q.step()) return std::nullopt;
  AttemptRow row{q.integer(0), q.integer(1), q.integer(2), q.integer(3), static_cast<TaskKind>(q.integer(4)),
                 static_cast<int>(q.integer(5)), static_cast<int>(q.integer(6)), static_cast<int>(q.integer(8)), {}};
  row.params.ParseFromString(q.blob(7));
  q.reset();
  return row;
}

std::optional<FarmState::AttemptTask> FarmState::runningAttemptTask(int64_t attemptId) {
  return transact([&]() -> std::optional<AttemptTask> {
    const auto attempt = currentAttempt(attemptId);
    if (!attempt) return std::nullopt;
    AttemptTask task{attempt->kind, attempt->params, {}};
    Statement& q = db_.query("SELECT spec FROM shots WHERE id = ?1").bind(1, attempt->shotId);
    if (q.step()) task.spec.ParseFromString(q.blob(0));
    q.reset();
    return task;
  });
}

HeartbeatReply FarmState::heartbeat(int64_t attemptId, double progress, double now) {
  return transact([&]() -> HeartbeatReply {
    HeartbeatReply reply;
    const auto attempt = currentAttempt(attemptId);
    if (!attempt) {
      reply.set_keep_going(false);
      return reply;
    }
    // SQLite evaluates every SET expression on the old row: progress_at moves only when
    // the progress does.
    db_.query("UPDATE attempts SET expires_at = ?1, progress_at = CASE WHEN ?2 > progress THEN ?3 ELSE progress_at END, "
              "progress = MAX(progress, ?2) WHERE id = ?4")
        .bind(1, now + settings_.leaseSeconds)
        .bind(2, std::isfinite(progress) ? std::clamp(progress, 0.0, 1.0) : 0.0)  // no number: no progress
        .bind(3, now)
        .bind(4, attemptId)
        .run();
    db_.query("UPDATE workers SET last_seen = ?1 WHERE id = ?2").bind(1, now).bind(2, attempt->workerId).run();
    reply.set_keep_going(true);
    reply.set_expires_in_seconds(settings_.leaseSeconds);
    return reply;
  });
}

void FarmState::endAttempt(const AttemptRow& attempt, int state, const std::string& error, double now,
                           const std::string& logTail, const std::string& failureClass) {
  // A worker's log is kept to its last kMaxLogTailBytes, whatever the worker sends.
  const std::string kept = logTail.size() > kMaxLogTailBytes ? logTail.substr(logTail.size() - kMaxLogTailBytes) : logTail;
  db_.query("UPDATE attempts SET state = ?1, finished_at = ?2, error = ?3, log_tail = ?4, failure_class = ?5 "
            "WHERE id = ?6")
      .bind(1, int64_t{state})
      .bind(2, now)
      .bind(3, error)
      .bind(4, kept)
      .bind(5, failureClass)
      .bind(6, attempt.id)
      .run();
  dropStaleFollowUps();
}

ReportReply FarmState::complete(const CompleteRequest& request, double now) {
  std::vector<std::string> released;
  const ReportReply reply = transact([&]() -> ReportReply {
    const ChunkRef& output = request.output();
    const auto attempt = currentAttempt(request.attempt_id());
    if (!attempt) return refused(kStaleLease);
    const bool hasOutput = attempt->kind != TASK_NOOP;
    if (hasOutput) {
      Statement& chunk = db_.query("SELECT 1 FROM chunks WHERE sha256 = ?1").bind(1, output.sha256());
      const bool stored = chunk.step();
      chunk.reset();
      if (!stored) return refused("the output chunk " + output.sha256() + " was not stored first");
    }
    addFollowUps(*attempt, now);  // before the attempt ends, which drops what it staged
    endAttempt(*attempt, static_cast<int>(AttemptState::Done), "", now, request.log_tail());
    Statement& done =
        db_.query("UPDATE tasks SET state = ?1, attempt_id = NULL, output_sha = ?2, core_seconds = ?3 WHERE id = ?4");
    done.bind(1, asInt(TaskState::Done));
    if (hasOutput) {
      done.bind(2, output.sha256());
    } else {
      done.bindNull(2);
    }
    done.bind(3, std::max(0.0, request.core_seconds())).bind(4, attempt->taskId).run();
    for (const auto& [name, value] : request.metrics()) {
      // SQLite stores NaN as NULL, which the column refuses: such a figure is left out and
      // said, and the task's output is kept (found by the rpc_handlers fuzz target).
      if (!std::isfinite(value)) {
        addEvent(attempt->shotId, "task " + std::to_string(attempt->taskId) + " reported a metric " +
                                      quotedInput(name) + " that is not a finite number; it is left out", now);
        continue;
      }
      db_.query("INSERT OR REPLACE INTO task_metrics (task_id, name, value) VALUES (?1, ?2, ?3)")
          .bind(1, attempt->taskId)
          .bind(2, name)
          .bind(3, value)
          .run();
    }
    db_.query("UPDATE tasks SET pending_deps = pending_deps - 1, state = CASE WHEN pending_deps = 1 AND state = ?1 "
              "THEN ?2 ELSE state END WHERE id IN (SELECT task_id FROM task_deps WHERE depends_on = ?3)")
        .bind(1, asInt(TaskState::Waiting))
        .bind(2, asInt(TaskState::Ready))
        .bind(3, attempt->taskId)
        .run();
    countTaskDone(attempt->shotId, now);
    released = releaseConsumedInputs(attempt->taskId);
    return accepted();
  });
  if (!released.empty()) {  // committed: their files may go
    const std::lock_guard lock(releasedMutex_);
    releasedChunks_.insert(releasedChunks_.end(), released.begin(), released.end());
  }
  return reply;
}

ReportReply FarmState::fail(int64_t attemptId, const std::string& reason, double now, const std::string& logTail,
                            FailureClass kind) {
  if (!FailureClass_IsValid(kind)) kind = FAILURE_WORKER_FAULT;  // a newer worker's class: the worker's doing
  return transact([&]() -> ReportReply {
    const auto attempt = currentAttempt(attemptId);
    if (!attempt) return refused(kStaleLease);
    endAttempt(*attempt, static_cast<int>(AttemptState::Failed), reason, now, logTail,
               lowerWithout(FailureClass_Name(kind), "FAILURE_"));
    // A worker leaving (a preempted node) is no fault of the task's, as a vanished one is
    // not; it only said so before its lease ran out.
    if (kind == FAILURE_RELEASED) {
      retryLost(*attempt, reason, now);
      return accepted();
    }
    // Bad input fails the shot once a second worker says so too: one worker (broken, or
    // hostile) cannot fail a shot by itself. Until then the task runs again, no one blamed.
    if (kind == FAILURE_BAD_INPUT && anotherWorkerFoundBadInput(*attempt)) {
      failOnBadInput(*attempt, reason, now);
    } else {
      retryOrFail(*attempt, reason, kind == FAILURE_WORKER_FAULT, now);
    }
    return accepted();
  });
}

bool FarmState::anotherWorkerFoundBadInput(const AttemptRow& attempt) {
  Statement& q = db_.query(
      "SELECT 1 FROM attempts WHERE task_id = ?1 AND id != ?2 AND worker_id != ?3 AND failure_class = 'bad_input'");
  q.bind(1, attempt.taskId).bind(2, attempt.id).bind(3, attempt.workerId);
  const bool found = q.step();
  q.reset();
  return found;
}

void FarmState::failOnBadInput(const AttemptRow& attempt, const std::string& reason, double now) {
  const std::string task = describeTask(attempt.taskId, attempt.kind, attempt.params);
  addEvent(attempt.shotId, task + " cannot run on any worker (bad input, reported by two workers, the last " +
                               std::to_string(attempt.workerId) + "): " + reason,
           now);
  failTask(attempt, "failures", attempt.failures + 1, task + " has a bad input: " + reason, now);
}

void FarmState::retryOrFail(const AttemptRow& attempt, const std::string& reason, bool blameWorker, double now) {
  const int failures = attempt.failures + 1;
  const std::string task = describeTask(attempt.taskId, attempt.kind, attempt.params);
  addEvent(attempt.shotId, task + " attempt " + std::to_string(failures) + " failed on worker " +
                               std::to_string(attempt.workerId) + ": " + reason,
           now);
  bool blocklisted = false;
  if (blameWorker) {
    db_.query("INSERT INTO worker_failures (shot_id, worker_id, failures) VALUES (?1, ?2, 1) "
              "ON CONFLICT (shot_id, worker_id) DO UPDATE SET failures = failures + 1")
        .bind(1, attempt.shotId)
        .bind(2, attempt.workerId)
        .run();
    db_.query("UPDATE worker_failures SET blocklisted = 1 WHERE shot_id = ?1 AND worker_id = ?2 AND failures >= ?3 "
              "AND blocklisted = 0")
        .bind(1, attempt.shotId)
        .bind(2, attempt.workerId)
        .bind(3, int64_t{settings_.blocklistAfter})
        .run();
    blocklisted = db_.changes() > 0;
    if (blocklisted)
      addEvent(attempt.shotId, "worker " + std::to_string(attempt.workerId) + " is blocklisted for this shot", now);
  }
  if (failures >= attempt.maxAttempts) {
    failTask(attempt, "failures", failures, task + " failed " + std::to_string(failures) + " times; last: " + reason, now);
    return;
  }
  if (blocklisted && !anyWorkerCanRun(attempt.shotId, now)) {
    endShot(attempt.shotId, SHOT_FAILED,
            "every live worker is blocklisted for this shot after repeated failures; last: " + reason, now);
    return;
  }
  const double backoff =
      std::min(settings_.maxBackoffSeconds, settings_.retryBackoffSeconds * std::pow(2.0, failures - 1));
  retryLater(attempt, "failures", failures, now + backoff);
}

void FarmState::failTask(const AttemptRow& attempt, const char* counter, int count, const std::string& why,
                         double now) {
  db_.query(std::string("UPDATE tasks SET state = ?1, ") + counter + " = ?2, attempt_id = NULL WHERE id = ?3")
      .bind(1, asInt(TaskState::Failed))
      .bind(2, int64_t{count})
      .bind(3, attempt.taskId)
      .run();
  endShot(attempt.shotId, SHOT_FAILED, why, now);
}

void FarmState::retryLater(const AttemptRow& attempt, const char* counter, int count, double notBefore) {
  db_.query(std::string("UPDATE tasks SET state = ?1, ") + counter +
            " = ?2, attempt_id = NULL, not_before = ?3 WHERE id = ?4")
      .bind(1, asInt(TaskState::Ready))
      .bind(2, int64_t{count})
      .bind(3, notBefore)
      .bind(4, attempt.taskId)
      .run();
}

void FarmState::retryLost(const AttemptRow& attempt, const std::string& reason, double now) {
  const int lost = attempt.lost + 1;
  const std::string task = describeTask(attempt.taskId, attempt.kind, attempt.params);
  addEvent(attempt.shotId, task + " lost worker " + std::to_string(attempt.workerId) + " (" + reason + "); loss " +
                               std::to_string(lost) + " of at most " + std::to_string(settings_.maxLostWorkers) +
                               ", not counted as a failure",
           now);
  if (lost >= settings_.maxLostWorkers) {
    failTask(attempt, "lost", lost,
             task + " lost its worker " + std::to_string(lost) + " times (it may be what kills them); last: " + reason,
             now);
    return;
  }
  retryLater(attempt, "lost", lost, now + settings_.retryBackoffSeconds);
}

int FarmState::expireLeases(double now) {
  return transact([&]() -> int {
    std::vector<std::pair<int64_t, bool>> ended;  // attempt, hung (rather than expired)
    Statement& q = db_.query(
        "SELECT id, expires_at < ?1 FROM attempts WHERE state = ?2 AND (expires_at < ?1 OR progress_at < ?3)");
    q.bind(1, now).bind(2, int64_t{kRunning}).bind(3, now - settings_.hungSeconds);
    while (q.step()) ended.emplace_back(q.integer(0), q.integer(1) == 0);
    int count = 0;
    for (const auto& [attemptId, hung] : ended) {
      const auto attempt = currentAttempt(attemptId);
      if (!attempt) continue;
      const std::string reason = hung ? "no progress for " + std::to_string(static_cast<int>(settings_.hungSeconds)) +
                                            " s: the task is hung and its lease was revoked"
                                      : "the lease expired: the worker stopped renewing it";
      endAttempt(*attempt, static_cast<int>(hung ? AttemptState::Revoked : AttemptState::Expired), reason, now);
      // A hung task is the task's doing; a vanished worker is not.
      if (hung) {
        retryOrFail(*attempt, reason, false, now);
      } else {
        retryLost(*attempt, reason, now);
      }
      ++count;
    }
    return count;
  });
}

bool FarmState::anyWorkerCanRun(int64_t shotId, double now) {
  // Live: asked for work or renewed a lease within two lease periods.
  Statement& q = db_.query(
      "SELECT COUNT(*) FROM workers WHERE last_seen >= ?1 AND id NOT IN "
      "(SELECT worker_id FROM worker_failures WHERE shot_id = ?2 AND blocklisted = 1)");
  q.bind(1, now - 2 * settings_.leaseSeconds).bind(2, shotId);
  q.step();
  const bool any = q.integer(0) > 0;
  q.reset();
  return any;
}

void FarmState::countTaskDone(int64_t shotId, double now) {
  db_.query("UPDATE shots SET tasks_left = tasks_left - 1 WHERE id = ?1").bind(1, shotId).run();
  Statement& q = db_.query("SELECT tasks_left FROM shots WHERE id = ?1").bind(1, shotId);
  q.step();
  const int64_t remaining = q.integer(0);
  q.reset();
  if (remaining == 0) endShot(shotId, SHOT_DONE, "", now);
}

void FarmState::endShot(int64_t shotId, ShotState state, const std::string& failure, double now) {
  db_.query("UPDATE shots SET state = ?1, finished_at = ?2, failure = ?3 WHERE id = ?4")
      .bind(1, int64_t{state})
      .bind(2, now)
      .bind(3, failure)
      .bind(4, shotId)
      .run();
  // Leases still out for this shot are revoked: their heartbeats are told to stop.
  db_.query("UPDATE attempts SET state = ?1, finished_at = ?2, error = 'the shot ended' "
            "WHERE state = ?3 AND task_id IN (SELECT id FROM tasks WHERE shot_id = ?4)")
      .bind(1, asInt(AttemptState::Revoked))
      .bind(2, now)
      .bind(3, int64_t{kRunning})
      .bind(4, shotId)
      .run();
  dropStaleFollowUps();
  db_.query("UPDATE tasks SET state = ?1, attempt_id = NULL WHERE shot_id = ?2 AND state = ?3")
      .bind(1, asInt(TaskState::Ready))
      .bind(2, shotId)
      .bind(3, asInt(TaskState::Leased))
      .run();
  addEvent(shotId, std::string(ShotState_Name(state)) + (failure.empty() ? "" : ": " + failure), now);
  if (state == SHOT_FAILED || state == SHOT_CANCELLED) failShotsWaitingFor(shotId, state, now);
}

void FarmState::failShotsWaitingFor(int64_t shotId, ShotState state, double now) {
  std::vector<int64_t> waiting;
  Statement& q = db_.query("SELECT w.shot_id FROM shot_waits w JOIN shots s ON s.id = w.shot_id "
                           "WHERE w.after_id = ?1 AND s.state IN (?2, ?3, ?4)");
  q.bind(1, shotId).bind(2, int64_t{SHOT_QUEUED}).bind(3, int64_t{SHOT_RUNNING}).bind(4, int64_t{SHOT_PAUSED});
  while (q.step()) waiting.push_back(q.integer(0));
  q.reset();
  // Each ends in turn, failing the shots that wait for it (a chain; no cycle, since a shot
  // waits only for shots submitted before it).
  for (const int64_t id : waiting)
    endShot(id, SHOT_FAILED, "shot " + std::to_string(shotId) + ", which it waits for, ended " + ShotState_Name(state),
            now);
}

void FarmState::addEvent(int64_t shotId, const std::string& message, double now) {
  db_.query("INSERT INTO events (shot_id, time, message) VALUES (?1, ?2, ?3)")
      .bind(1, shotId)
      .bind(2, now)
      .bind(3, message)
      .run();
}

void FarmState::recordChunk(const ChunkRef& chunk, double now) {
  return transact([&]() -> void {
    db_.query("INSERT INTO chunks (sha256, size, stored_at) VALUES (?1, ?2, ?3) "
              "ON CONFLICT (sha256) DO UPDATE SET released = 0")
        .bind(1, chunk.sha256())
        .bind(2, chunk.size())
        .bind(3, now)
        .run();
  });
}

bool FarmState::hasChunk(const std::string& sha256) {
  return transact([&]() -> bool {
    Statement& q = db_.query("SELECT 1 FROM chunks WHERE sha256 = ?1").bind(1, sha256);
    const bool found = q.step();
    q.reset();
    return found;
  });
}

}  // namespace pathfarm::farm
