// FarmState's reads for the dashboard: a shot's tasks with their attempts, and the
// attempts running on the workers now.
#include "scheduler/farm_state.h"
#include "scheduler/farm_state_internal.h"

namespace pathfarm::farm {

FarmState::TaskPage FarmState::taskDetails(int64_t shotId, std::optional<int> state, int64_t offset, int64_t limit) {
  return transact([&]() -> TaskPage {
    summaryLocked(shotId, 0);  // throws std::out_of_range for an unknown shot
    // ?2 = -1 matches every state.
    const int64_t stateFilter = state ? *state : -1;
    TaskPage page;
    Statement& count = db_.query("SELECT COUNT(*) FROM tasks WHERE shot_id = ?1 AND (?2 = -1 OR state = ?2)");
    count.bind(1, shotId).bind(2, stateFilter);
    count.step();
    page.matching = count.integer(0);
    count.reset();

    Statement& tasks = db_.query(
        "SELECT id, kind, params, state, failures, lost, max_attempts, core_seconds FROM tasks "
        "WHERE shot_id = ?1 AND (?2 = -1 OR state = ?2) ORDER BY id LIMIT ?3 OFFSET ?4");
    tasks.bind(1, shotId).bind(2, stateFilter).bind(3, limit).bind(4, offset);
    while (tasks.step()) {
      TaskDetail& task = page.tasks.emplace_back();
      task.id = tasks.integer(0);
      task.kind = static_cast<TaskKind>(tasks.integer(1));
      task.params.ParseFromString(tasks.blob(2));
      task.state = static_cast<int>(tasks.integer(3));
      task.failures = tasks.integer(4);
      task.lost = tasks.integer(5);
      task.maxAttempts = tasks.integer(6);
      task.coreSeconds = tasks.real(7);
    }
    for (TaskDetail& task : page.tasks) {
      Statement& attempts = db_.query(
          "SELECT a.id, a.worker_id, COALESCE(w.name, ''), a.state, a.leased_at, a.finished_at, a.progress, a.error, "
          "a.log_tail, a.failure_class FROM attempts a LEFT JOIN workers w ON w.id = a.worker_id WHERE a.task_id = ?1 ORDER BY a.id");
      attempts.bind(1, task.id);
      while (attempts.step()) {
        AttemptDetail& attempt = task.attempts.emplace_back();
        attempt.id = attempts.integer(0);
        attempt.workerId = attempts.integer(1);
        attempt.workerName = attempts.text(2);
        attempt.state = static_cast<int>(attempts.integer(3));
        attempt.leasedAt = attempts.real(4);
        if (!attempts.isNull(5)) attempt.finishedAt = attempts.real(5);
        attempt.progress = attempts.real(6);
        attempt.error = attempts.text(7);
        attempt.logTail = attempts.text(8);
        attempt.failureClass = attempts.text(9);
      }
    }
    return page;
  });
}

std::vector<FarmState::RunningTask> FarmState::runningTasks() {
  return transact([&] {
    return db_
        .query("SELECT a.worker_id, t.shot_id, t.id, a.id, t.kind, t.params, a.leased_at, a.progress "
               "FROM attempts a JOIN tasks t ON t.id = a.task_id WHERE a.state = ?1 ORDER BY a.worker_id, a.id")
        .bind(1, int64_t{kRunning})
        .rows([](const Statement& q) {
          RunningTask task;
          task.workerId = q.integer(0);
          task.shotId = q.integer(1);
          task.taskId = q.integer(2);
          task.attemptId = q.integer(3);
          task.kind = static_cast<TaskKind>(q.integer(4));
          TaskParams params;
          params.ParseFromString(q.blob(5));
          task.frame = params.frame();
          task.leasedAt = q.real(6);
          task.progress = q.real(7);
          return task;
        });
  });
}

}  // namespace pathfarm::farm
