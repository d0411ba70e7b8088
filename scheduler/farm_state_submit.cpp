// FarmState's submit: a shot's tasks are inserted a batch per transaction, so a shot of a
// million tasks never holds the farm's lock for long (heartbeats and leases of other
// shots go on between batches). Until its last batch the shot is "building": no task of
// it is leased, and a scheduler that starts with a shot still building deletes it, since
// its submit never returned (the client's retry makes it again).
#include <algorithm>

#include "scheduler/farm_state.h"
#include "scheduler/farm_state_internal.h"

namespace pathfarm::farm {

void FarmState::checkShotsWaitedFor(const ShotSpec& spec) {
  for (const int64_t after : spec.after_shots()) {
    Statement& q = db_.query("SELECT state FROM shots WHERE id = ?1").bind(1, after);
    const bool found = q.step();
    const auto state = found ? static_cast<ShotState>(q.integer(0)) : SHOT_STATE_UNSPECIFIED;
    q.reset();
    if (!found) throw std::invalid_argument("after_shots: shot " + std::to_string(after) + " does not exist");
    if (state == SHOT_FAILED || state == SHOT_CANCELLED)
      throw std::invalid_argument("after_shots: shot " + std::to_string(after) + " ended " + ShotState_Name(state) +
                                  "; a shot waiting for it could never start");
  }
}

int64_t FarmState::submit(const ShotSpec& spec, const std::vector<PlannedTask>& plan, double now,
                          const std::string& submitKey) {
  std::optional<int64_t> earlier;
  const int64_t shotId = transact([&]() -> int64_t {
    if (!submitKey.empty()) {
      Statement& lookup = db_.query("SELECT id FROM shots WHERE submit_key = ?1").bind(1, submitKey);
      if (lookup.step()) earlier = lookup.integer(0);
      lookup.reset();
      if (earlier) return *earlier;
    }
    checkShotsWaitedFor(spec);
    Statement& insert = db_.query(
        "INSERT INTO shots (name, spec, state, priority, tasks_left, submitted_at, submit_key, required_tags, "
        "max_workers, building) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, 1)");
    insert.bind(1, spec.name())
        .bindBlob(2, spec.SerializeAsString())
        .bind(3, int64_t{SHOT_QUEUED})
        .bind(4, int64_t{spec.priority()})
        .bind(5, static_cast<int64_t>(plan.size()))
        .bind(6, now)
        .bind(8, tagList(spec.required_tags().begin(), spec.required_tags().end()))
        .bind(9, int64_t{std::max(0, spec.max_workers())});
    if (submitKey.empty()) {
      insert.bindNull(7);
    } else {
      insert.bind(7, submitKey);
    }
    insert.run();
    const int64_t id = db_.lastInsertId();
    for (const int64_t after : spec.after_shots())
      db_.query("INSERT OR IGNORE INTO shot_waits (shot_id, after_id) VALUES (?1, ?2)").bind(1, id).bind(2, after).run();
    return id;
  });
  if (earlier) return shotId;  // a retried submit: that one is building or built the shot

  try {
    const int64_t maxAttempts = spec.max_attempts() > 0 ? spec.max_attempts() : settings_.defaultMaxAttempts;
    std::vector<int64_t> ids;
    ids.reserve(plan.size());
    for (size_t first = 0; first < plan.size(); first += kTasksPerTransaction) {
      transact([&] {
        const size_t end = std::min(plan.size(), first + kTasksPerTransaction);
        for (size_t i = first; i < end; ++i) {
          const PlannedTask& task = plan[i];
          ids.push_back(insertTask(shotId, task.kind, task.params, task.dependencies.size(), maxAttempts, task.output));
          for (const size_t dependency : task.dependencies)
            db_.query("INSERT INTO task_deps (task_id, depends_on) VALUES (?1, ?2)")
                .bind(1, ids.back())
                .bind(2, ids.at(dependency))
                .run();
        }
      });
    }
    transact([&] {
      db_.query("UPDATE shots SET building = 0 WHERE id = ?1").bind(1, shotId).run();
      addEvent(shotId, "submitted: " + std::to_string(plan.size()) + " tasks", now);
      if (spec.after_shots_size() > 0) {
        std::string waits;
        for (const int64_t after : spec.after_shots()) waits += (waits.empty() ? "" : ", ") + std::to_string(after);
        addEvent(shotId, "waits for shot " + waits + " to be done", now);
      }
    });
  } catch (...) {
    transact([&] { db_.query("DELETE FROM shots WHERE id = ?1").bind(1, shotId).run(); });
    throw;
  }
  return shotId;
}

int64_t FarmState::insertTask(int64_t shotId, TaskKind kind, const TaskParams& params, size_t dependencies,
                              int64_t maxAttempts, bool output) {
  db_.query("INSERT INTO tasks (shot_id, kind, params, state, pending_deps, max_attempts, is_output) "
            "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7)")
      .bind(1, shotId)
      .bind(2, int64_t{kind})
      .bindBlob(3, params.SerializeAsString())
      .bind(4, asInt(dependencies == 0 ? TaskState::Ready : TaskState::Waiting))
      .bind(5, static_cast<int64_t>(dependencies))
      .bind(6, maxAttempts)
      .bind(7, int64_t{output})
      .run();
  return db_.lastInsertId();
}

}  // namespace pathfarm::farm
