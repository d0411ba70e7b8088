// FarmState::metrics: the figures /metrics serves (scheduler/farm_metrics.h), read in one
// transaction so that they agree with each other.
#include "scheduler/farm_metrics.h"
#include "scheduler/farm_names.h"
#include "scheduler/farm_state.h"
#include "scheduler/farm_state_internal.h"

namespace pathfarm::farm {
namespace {

std::string kindName(int64_t kind) { return lowerWithout(TaskKind_Name(static_cast<TaskKind>(kind)), "TASK_"); }

}  // namespace

FarmMetrics FarmState::metrics(double now) {
  return transact([&]() -> FarmMetrics { return metricsLocked(now); });
}

FarmMetrics FarmState::metricsLocked(double now) {
  FarmMetrics m;
  Statement& tasks = db_.query("SELECT kind, state, COUNT(*) FROM tasks GROUP BY kind, state");
  while (tasks.step())
    m.tasks[{kindName(tasks.integer(0)), taskStateName(static_cast<int>(tasks.integer(1)))}] = tasks.integer(2);

  // Busy: holding a lease; idle: seen within two lease periods (as anyWorkerCanRun counts
  // the live ones); gone: neither.
  Statement& workers = db_.query(
      "SELECT CASE WHEN EXISTS (SELECT 1 FROM attempts a WHERE a.worker_id = w.id AND a.state = ?1) THEN 'busy' "
      "WHEN w.last_seen >= ?2 THEN 'idle' ELSE 'gone' END AS s, COUNT(*) FROM workers w GROUP BY s");
  workers.bind(1, asInt(AttemptState::Running)).bind(2, now - 2 * settings_.leaseSeconds);
  for (const char* state : {"busy", "idle", "gone"}) m.workers[state] = 0;
  while (workers.step()) m.workers[workers.text(0)] = workers.integer(1);

  const std::vector<double>& bounds = durationBuckets();
  std::string bucketColumns;
  for (size_t b = 0; b < bounds.size(); ++b)
    bucketColumns += ", SUM(d <= " + std::to_string(bounds[b]) + ")";
  Statement& durations = db_.query(
      "SELECT kind, COUNT(*), SUM(d)" + bucketColumns +
      " FROM (SELECT t.kind AS kind, a.finished_at - a.leased_at AS d FROM attempts a JOIN tasks t ON t.id = a.task_id "
      "WHERE a.state = ?1) GROUP BY kind");
  durations.bind(1, asInt(AttemptState::Done));
  while (durations.step()) {
    FarmMetrics::Durations& d = m.durations[kindName(durations.integer(0))];
    d.count = static_cast<uint64_t>(durations.integer(1));
    d.sum = durations.real(2);
    for (size_t b = 0; b < bounds.size(); ++b)
      d.cumulative.push_back(static_cast<uint64_t>(durations.integer(static_cast<int>(3 + b))));
  }

  // A failed attempt by the class its worker reported (attempts from before classes were
  // kept count as worker faults).
  for (const char* cause : {"worker_fault", "bad_input", "transport", "released", "lost", "revoked"}) m.attemptsEnded[cause] = 0;
  Statement& ended = db_.query(
      "SELECT CASE state WHEN ?1 THEN CASE failure_class WHEN '' THEN 'worker_fault' ELSE failure_class END "
      "WHEN ?2 THEN 'lost' ELSE 'revoked' END, COUNT(*) FROM attempts WHERE state IN (?1, ?2, ?3) GROUP BY 1");
  ended.bind(1, asInt(AttemptState::Failed))
      .bind(2, asInt(AttemptState::Expired))
      .bind(3, asInt(AttemptState::Revoked));
  while (ended.step()) m.attemptsEnded[ended.text(0)] = ended.integer(1);

  Statement& shots = db_.query(
      "SELECT s.id, s.name, s.state, (SELECT COUNT(*) FROM tasks t WHERE t.shot_id = s.id), s.tasks_left FROM shots s");
  while (shots.step()) {
    const auto state = static_cast<ShotState>(shots.integer(2));
    ++m.shots[lowerWithout(ShotState_Name(state), "SHOT_")];
    if (state != SHOT_QUEUED && state != SHOT_RUNNING) continue;
    const auto total = static_cast<double>(shots.integer(3));
    m.progress.push_back({shots.integer(0), shots.text(1),
                          total > 0 ? 1.0 - static_cast<double>(shots.integer(4)) / total : 0.0});
  }
  return m;
}

}  // namespace pathfarm::farm
