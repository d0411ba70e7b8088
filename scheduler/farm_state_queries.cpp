// FarmState's reads of shots, outputs, task records and workers, and the user's
// controls of a shot (cancel, pause, resume, retry).
#include <functional>

#include "scheduler/farm_state.h"
#include "scheduler/farm_state_internal.h"

namespace pathfarm::farm {

ShotSummary FarmState::summaryLocked(int64_t shotId, double now) {
  ShotSummary summary;
  Statement& shot = db_.query(
      "SELECT name, state, priority, submitted_at, finished_at, failure FROM shots WHERE id = ?1");
  shot.bind(1, shotId);
  if (!shot.step()) throw std::out_of_range("no shot " + std::to_string(shotId));
  summary.set_id(shotId);
  summary.set_name(shot.text(0));
  summary.set_state(static_cast<ShotState>(shot.integer(1)));
  summary.set_priority(static_cast<int32_t>(shot.integer(2)));
  const double end = shot.isNull(4) ? now : shot.real(4);
  summary.set_elapsed_seconds(end - shot.real(3));
  summary.set_failure(shot.text(5));
  shot.reset();

  Statement& tasks = db_.query(
      "SELECT COUNT(*), TOTAL(state = ?2), TOTAL(state = ?3), TOTAL(state = ?4), TOTAL(is_output), "
      "TOTAL(is_output AND state = ?2) FROM tasks WHERE shot_id = ?1");
  tasks.bind(1, shotId)
      .bind(2, asInt(TaskState::Done))
      .bind(3, asInt(TaskState::Leased))
      .bind(4, asInt(TaskState::Failed));
  tasks.step();
  summary.set_tasks_total(tasks.integer(0));
  summary.set_tasks_done(static_cast<int64_t>(tasks.real(1)));
  summary.set_tasks_running(static_cast<int64_t>(tasks.real(2)));
  summary.set_tasks_failed(static_cast<int64_t>(tasks.real(3)));
  summary.set_frames_total(static_cast<int64_t>(tasks.real(4)));
  summary.set_frames_done(static_cast<int64_t>(tasks.real(5)));
  tasks.reset();

  Statement& attempts = db_.query(
      "SELECT COUNT(*), COUNT(DISTINCT CASE WHEN a.state = ?2 THEN a.worker_id END) "
      "FROM attempts a JOIN tasks t ON t.id = a.task_id WHERE t.shot_id = ?1");
  attempts.bind(1, shotId).bind(2, int64_t{kRunning});
  attempts.step();
  summary.set_attempts(attempts.integer(0));
  summary.set_workers_busy(static_cast<int32_t>(attempts.integer(1)));
  attempts.reset();
  return summary;
}

ShotSummary FarmState::summary(int64_t shotId, double now) {
  return transact([&]() -> ShotSummary {
    ShotSummary s = summaryLocked(shotId, now);
    return s;
  });
}

ShotReply FarmState::shot(int64_t shotId, double now) {
  return transact([&]() -> ShotReply {
    ShotReply reply;
    *reply.mutable_summary() = summaryLocked(shotId, now);
    Statement& spec = db_.query("SELECT spec FROM shots WHERE id = ?1").bind(1, shotId);
    spec.step();
    reply.mutable_spec()->ParseFromString(spec.blob(0));
    spec.reset();
    Statement& events = db_.query("SELECT time, message FROM events WHERE shot_id = ?1 ORDER BY id");
    events.bind(1, shotId);
    while (events.step()) {
      ShotEvent* event = reply.add_events();
      event->set_shot_id(shotId);
      event->set_time(events.real(0));
      event->set_message(events.text(1));
    }
    return reply;
  });
}

std::vector<ShotSummary> FarmState::shots(double now) {
  return transact([&]() -> std::vector<ShotSummary> {
    std::vector<int64_t> ids;
    Statement& q = db_.query("SELECT id FROM shots ORDER BY id");
    while (q.step()) ids.push_back(q.integer(0));
    std::vector<ShotSummary> out;
    for (const int64_t id : ids) out.push_back(summaryLocked(id, now));
    return out;
  });
}

void FarmState::setShotState(int64_t shotId, ShotState state, double now) {
  db_.query("UPDATE shots SET state = ?1 WHERE id = ?2").bind(1, int64_t{state}).bind(2, shotId).run();
  addEvent(shotId, ShotState_Name(state), now);
}

template <class Change>
ShotSummary FarmState::changeShot(int64_t shotId, double now, Change change) {
  return transact([&]() -> ShotSummary {
    change(summaryLocked(shotId, now).state());
    return summaryLocked(shotId, now);
  });
}

ShotSummary FarmState::cancel(int64_t shotId, double now) {
  return changeShot(shotId, now, [&](ShotState state) {
    if (!isFinished(state)) endShot(shotId, SHOT_CANCELLED, "", now);
  });
}

ShotSummary FarmState::pause(int64_t shotId, double now) {
  return changeShot(shotId, now, [&](ShotState state) {
    if (isActive(state)) setShotState(shotId, SHOT_PAUSED, now);
  });
}

ShotSummary FarmState::resume(int64_t shotId, double now) {
  return changeShot(shotId, now, [&](ShotState state) {
    if (state == SHOT_PAUSED) reactivate(shotId, now);
  });
}

void FarmState::reactivate(int64_t shotId, double now) {
  Statement& q = db_.query("SELECT started_at IS NOT NULL FROM shots WHERE id = ?1").bind(1, shotId);
  q.step();
  const bool started = q.integer(0) != 0;
  q.reset();
  setShotState(shotId, started ? SHOT_RUNNING : SHOT_QUEUED, now);
}

ShotSummary FarmState::retry(int64_t shotId, double now) {
  return changeShot(shotId, now, [&](ShotState state) {
    if (state != SHOT_FAILED) return;
    db_.query("UPDATE tasks SET state = ?1, failures = 0, lost = 0, not_before = 0 WHERE shot_id = ?2 AND state = ?3")
        .bind(1, asInt(TaskState::Ready))
        .bind(2, shotId)
        .bind(3, asInt(TaskState::Failed))
        .run();
    const int64_t restarted = db_.changes();
    db_.query("DELETE FROM worker_failures WHERE shot_id = ?1").bind(1, shotId).run();
    db_.query("UPDATE shots SET finished_at = NULL, failure = '' WHERE id = ?1").bind(1, shotId).run();
    addEvent(shotId, "retried: " + std::to_string(restarted) + " failed task(s) start over; what is done stays done",
             now);
    reactivate(shotId, now);
  });
}

std::vector<std::pair<int64_t, ChunkRef>> FarmState::outputs(int64_t shotId) {
  return doneFrames(shotId, "t.is_output", [](const TaskParams&) { return true; });
}

std::vector<std::pair<int64_t, ChunkRef>> FarmState::references(int64_t shotId) {
  return doneFrames(shotId, "t.kind = " + std::to_string(int{TASK_ASSEMBLE_FRAME}), [](const TaskParams& params) {
    return params.role() == ROLE_REFERENCE && !params.has_window();  // a whole frame, not a region
  });
}

std::vector<std::pair<int64_t, ChunkRef>> FarmState::doneFrames(
    int64_t shotId, const std::string& condition, const std::function<bool(const TaskParams&)>& keep) {
  return transact([&]() -> std::vector<std::pair<int64_t, ChunkRef>> {
    std::vector<std::pair<int64_t, ChunkRef>> out;
    Statement& q = db_.query(
        "SELECT t.params, c.sha256, c.size FROM tasks t JOIN chunks c ON c.sha256 = t.output_sha "
        "WHERE t.shot_id = ?1 AND " + condition + " AND t.state = ?2 ORDER BY t.id");
    q.bind(1, shotId).bind(2, asInt(TaskState::Done));
    while (q.step()) {
      TaskParams params;
      params.ParseFromString(q.blob(0));
      if (!keep(params)) continue;
      ChunkRef ref;
      ref.set_sha256(q.text(1));
      ref.set_size(q.integer(2));
      out.emplace_back(params.frame(), ref);
    }
    return out;
  });
}

std::pair<ShotSpec, std::vector<TaskRecord>> FarmState::taskRecords(int64_t shotId) {
  return transact([&]() -> std::pair<ShotSpec, std::vector<TaskRecord>> {
    ShotSpec spec;
    Statement& shot = db_.query("SELECT spec FROM shots WHERE id = ?1").bind(1, shotId);
    if (!shot.step()) throw std::out_of_range("no shot " + std::to_string(shotId));
    spec.ParseFromString(shot.blob(0));
    shot.reset();
    std::vector<TaskRecord> records;
    Statement& q = db_.query("SELECT id, kind, params, state = ?2, core_seconds, output_sha FROM tasks WHERE shot_id = ?1 ORDER BY id");
    q.bind(1, shotId).bind(2, asInt(TaskState::Done));
    while (q.step()) {
      TaskRecord record;
      record.kind = static_cast<TaskKind>(q.integer(1));
      record.params.ParseFromString(q.blob(2));
      record.done = q.integer(3) != 0;
      record.coreSeconds = q.real(4);
      if (record.done) record.outputSha = q.text(5);
      records.push_back(std::move(record));
      Statement& metrics = db_.query("SELECT name, value FROM task_metrics WHERE task_id = ?1").bind(1, q.integer(0));
      while (metrics.step()) records.back().metrics[metrics.text(0)] = metrics.real(1);
    }
    return {spec, records};
  });
}

std::vector<WorkerInfo> FarmState::workers(double now) {
  return transact([&] {
    return db_
        .query("SELECT w.id, w.name, w.slots, w.last_seen, (SELECT COUNT(*) FROM attempts a WHERE a.worker_id = w.id "
               "AND a.state = ?1) FROM workers w ORDER BY w.id")
        .bind(1, int64_t{kRunning})
        .rows([&](const Statement& q) {
          WorkerInfo info;
          info.set_id(q.integer(0));
          info.set_name(q.text(1));
          info.set_slots(static_cast<int32_t>(q.integer(2)));
          info.set_seconds_since_seen(now - q.real(3));
          info.set_busy(static_cast<int32_t>(q.integer(4)));
          return info;
        });
  });
}

ShotSummary FarmState::setPriority(int64_t shotId, int priority, double now) {
  return changeShot(shotId, now, [&](ShotState) {
    db_.query("UPDATE shots SET priority = ?1 WHERE id = ?2").bind(1, int64_t{priority}).bind(2, shotId).run();
    addEvent(shotId, "priority set to " + std::to_string(priority), now);
  });
}

std::vector<BlocklistEntry> FarmState::blocklist(int64_t shotId) {
  return transact([&]() -> std::vector<BlocklistEntry> {
    std::vector<BlocklistEntry> entries;
    Statement& q = db_.query(
        "SELECT f.shot_id, f.worker_id, w.name, f.failures FROM worker_failures f JOIN workers w ON w.id = f.worker_id "
        "WHERE f.blocklisted AND (?1 = 0 OR f.shot_id = ?1) ORDER BY f.shot_id, f.worker_id");
    q.bind(1, shotId);
    while (q.step()) {
      BlocklistEntry& e = entries.emplace_back();
      e.set_shot_id(q.integer(0));
      e.set_worker_id(q.integer(1));
      e.set_worker_name(q.text(2));
      e.set_failures(static_cast<int32_t>(q.integer(3)));
    }
    return entries;
  });
}

void FarmState::clearBlocklist(int64_t shotId, int64_t workerId, double now) {
  transact([&] {
    summaryLocked(shotId, now);  // throws std::out_of_range for an unknown shot
    db_.query("DELETE FROM worker_failures WHERE shot_id = ?1 AND (?2 = 0 OR worker_id = ?2)")
        .bind(1, shotId)
        .bind(2, workerId)
        .run();
    addEvent(shotId,
             workerId == 0 ? "blocklist cleared" : "worker " + std::to_string(workerId) + " taken off the blocklist",
             now);
  });
}

}  // namespace pathfarm::farm
