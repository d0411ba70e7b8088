// Requeueing: a task or a frame runs again, with everything that used its output.
#include <map>
#include <stdexcept>

#include "scheduler/farm_state_internal.h"

namespace pathfarm::farm {
namespace {

// The scratch table of one requeue: the tasks that run again.
constexpr const char* kScratch = "CREATE TEMP TABLE IF NOT EXISTS requeued (id INTEGER PRIMARY KEY); DELETE FROM requeued;";

}  // namespace

ShotSummary FarmState::requeueTask(int64_t shotId, int64_t taskId, double now) {
  return transact([&]() -> ShotSummary {
    summaryLocked(shotId, now);  // an unknown shot throws std::out_of_range
    Statement& q = db_.query("SELECT 1 FROM tasks WHERE id = ?1 AND shot_id = ?2").bind(1, taskId).bind(2, shotId);
    const bool found = q.step();
    q.reset();
    if (!found)
      throw std::out_of_range("shot " + std::to_string(shotId) + " has no task " + std::to_string(taskId));
    return requeueLocked(shotId, {taskId}, "task " + std::to_string(taskId), now);
  });
}

ShotSummary FarmState::requeueFrame(int64_t shotId, int64_t frame, double now) {
  return transact([&]() -> ShotSummary {
    summaryLocked(shotId, now);
    std::vector<int64_t> seeds;
    Statement& q = db_.query("SELECT id, params FROM tasks WHERE shot_id = ?1 AND kind != ?2");
    q.bind(1, shotId).bind(2, int64_t{TASK_EVALUATE});
    while (q.step()) {
      TaskParams params;
      params.ParseFromString(q.blob(1));
      if (params.frame() == frame) seeds.push_back(q.integer(0));
    }
    if (seeds.empty())
      throw std::out_of_range("shot " + std::to_string(shotId) + " has no task for frame " + std::to_string(frame));
    return requeueLocked(shotId, seeds, "frame " + std::to_string(frame), now);
  });
}

int FarmState::requeueProducersOf(const std::string& sha256, double now) {
  return transact([&]() -> int {
    std::map<int64_t, std::vector<int64_t>> producersByShot;
    // A chunk released on purpose (no reader waited) is made again only for a reader.
    Statement& q = db_.query(
        "SELECT t.shot_id, t.id FROM tasks t JOIN shots s ON s.id = t.shot_id "
        "WHERE t.output_sha = ?1 AND t.state = ?2 AND s.state NOT IN (?3, ?4) "
        "AND (NOT EXISTS (SELECT 1 FROM chunks c WHERE c.sha256 = ?1 AND c.released = 1) OR EXISTS "
        "(SELECT 1 FROM task_deps d JOIN tasks r ON r.id = d.task_id WHERE d.depends_on = t.id AND r.state != ?2))");
    q.bind(1, sha256).bind(2, asInt(TaskState::Done)).bind(3, int64_t{SHOT_FAILED}).bind(4, int64_t{SHOT_CANCELLED});
    while (q.step()) producersByShot[q.integer(0)].push_back(q.integer(1));
    int requeued = 0;
    for (const auto& [shotId, producers] : producersByShot) {
      requeueLocked(shotId, producers, "the output chunk " + sha256.substr(0, 12) + " was missing or damaged", now);
      requeued += static_cast<int>(producers.size());
    }
    return requeued;
  });
}

ShotSummary FarmState::requeueLocked(int64_t shotId, const std::vector<int64_t>& seeds, const std::string& what,
                                     double now) {
  const ShotState state = summaryLocked(shotId, now).state();
  if (state == SHOT_CANCELLED) throw std::invalid_argument("shot " + std::to_string(shotId) + " was cancelled");
  if (state == SHOT_FAILED)
    throw std::invalid_argument("shot " + std::to_string(shotId) +
                                " failed: `pathfarm retry` it first, then requeue what should run again");
  db_.execute(kScratch);
  for (const int64_t id : seeds) db_.query("INSERT OR IGNORE INTO requeued (id) VALUES (?1)").bind(1, id).run();
  // Everything downstream: a task whose input runs again must run again too.
  db_.execute(
      "WITH RECURSIVE downstream(id) AS (SELECT id FROM requeued "
      "UNION SELECT d.task_id FROM task_deps d JOIN downstream s ON d.depends_on = s.id) "
      "INSERT OR IGNORE INTO requeued (id) SELECT id FROM downstream;");

  // Re-render tiles asked for by a task that runs again are dropped: it asks again.
  Statement& dropped = db_.query(
      "SELECT COUNT(*), COALESCE(SUM(state != ?1), 0) FROM tasks WHERE created_by IN (SELECT id FROM requeued)");
  dropped.bind(1, asInt(TaskState::Done));
  dropped.step();
  const int64_t droppedTiles = dropped.integer(0);
  const int64_t droppedUnfinished = dropped.integer(1);
  dropped.reset();
  db_.execute("DELETE FROM requeued WHERE id IN (SELECT id FROM tasks WHERE created_by IN (SELECT id FROM requeued));");
  db_.query("UPDATE attempts SET state = ?1, finished_at = ?2, error = 'requeued' WHERE state = ?3 AND task_id IN "
            "(SELECT id FROM tasks WHERE id IN (SELECT id FROM requeued) OR created_by IN (SELECT id FROM requeued))")
      .bind(1, asInt(AttemptState::Revoked))
      .bind(2, now)
      .bind(3, int64_t{kRunning})
      .run();
  dropStaleFollowUps();
  db_.execute(
      "DELETE FROM task_deps WHERE depends_on IN (SELECT id FROM tasks WHERE created_by IN (SELECT id FROM requeued));"
      "DELETE FROM tasks WHERE created_by IN (SELECT id FROM requeued);");

  Statement& done = db_.query("SELECT COUNT(*) FROM tasks WHERE state = ?1 AND id IN (SELECT id FROM requeued)");
  done.bind(1, asInt(TaskState::Done));
  done.step();
  const int64_t undone = done.integer(0);
  done.reset();
  Statement& count = db_.query("SELECT COUNT(*) FROM requeued");
  count.step();
  const int64_t requeued = count.integer(0);
  count.reset();

  // A dependency counts as pending when it is not done or runs again itself.
  db_.query("UPDATE tasks SET pending_deps = (SELECT COUNT(*) FROM task_deps d JOIN tasks t ON t.id = d.depends_on "
            "WHERE d.task_id = tasks.id AND (t.state != ?1 OR t.id IN (SELECT id FROM requeued))), "
            "failures = 0, lost = 0, not_before = 0, attempt_id = NULL, output_sha = NULL, core_seconds = 0 "
            "WHERE id IN (SELECT id FROM requeued)")
      .bind(1, asInt(TaskState::Done))
      .run();
  db_.query("UPDATE tasks SET state = CASE WHEN pending_deps = 0 THEN ?1 ELSE ?2 END "
            "WHERE id IN (SELECT id FROM requeued)")
      .bind(1, asInt(TaskState::Ready))
      .bind(2, asInt(TaskState::Waiting))
      .run();
  db_.execute("DELETE FROM task_metrics WHERE task_id IN (SELECT id FROM requeued);");
  db_.query("UPDATE shots SET tasks_left = tasks_left + ?1 - ?2 WHERE id = ?3")
      .bind(1, undone)
      .bind(2, droppedUnfinished)
      .bind(3, shotId)
      .run();
  addEvent(shotId,
           "requeued " + what + ": " + std::to_string(requeued) + " task(s) run again" +
               (droppedTiles > 0 ? ", " + std::to_string(droppedTiles) + " re-render tile(s) dropped" : ""),
           now);
  if (state == SHOT_DONE) {
    db_.query("UPDATE shots SET finished_at = NULL WHERE id = ?1").bind(1, shotId).run();
    reactivate(shotId, now);
  }
  return summaryLocked(shotId, now);
}

}  // namespace pathfarm::farm
