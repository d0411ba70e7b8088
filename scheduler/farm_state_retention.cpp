// FarmState's retention: finished shots past settings().retainSeconds are deleted, and the
// chunks nothing kept needs any more; render tiles go from the store once consumed.
#include <utility>

#include "scheduler/farm_state.h"
#include "scheduler/farm_state_internal.h"

namespace pathfarm::farm {

FarmState::Collected FarmState::collectGarbage(double now) {
  if (settings_.retainSeconds <= 0) return {};
  const double before = now - settings_.retainSeconds;
  return transact([&]() -> Collected {
    Collected collected;
    Statement& old = db_.query("SELECT id FROM shots WHERE state IN (?1, ?2, ?3) AND finished_at < ?4");
    old.bind(1, int64_t{SHOT_DONE}).bind(2, int64_t{SHOT_FAILED}).bind(3, int64_t{SHOT_CANCELLED}).bind(4, before);
    while (old.step()) collected.shots.push_back(old.integer(0));
    // Tasks, their dependencies, attempts, metrics, events and blocklist entries go with
    // the shot (ON DELETE CASCADE).
    for (const int64_t shot : collected.shots) db_.query("DELETE FROM shots WHERE id = ?1").bind(1, shot).run();

    // The scene files of the shots kept are named only inside their specs.
    db_.execute("CREATE TEMP TABLE IF NOT EXISTS kept_inputs (sha256 TEXT PRIMARY KEY); DELETE FROM kept_inputs;");
    std::vector<std::string> inputs;
    Statement& specs = db_.query("SELECT spec FROM shots");
    while (specs.step()) {
      ShotSpec spec;
      spec.ParseFromString(specs.blob(0));
      for (const InputFile& file : spec.inputs()) inputs.push_back(file.chunk().sha256());
    }
    for (const std::string& sha : inputs)
      db_.query("INSERT OR IGNORE INTO kept_inputs (sha256) VALUES (?1)").bind(1, sha).run();
    Statement& unused = db_.query(
        "SELECT sha256 FROM chunks WHERE stored_at < ?1 AND sha256 NOT IN (SELECT sha256 FROM kept_inputs) "
        "AND NOT EXISTS (SELECT 1 FROM tasks WHERE output_sha = chunks.sha256)");
    unused.bind(1, before);
    while (unused.step()) collected.chunks.push_back(unused.text(0));
    for (const std::string& sha : collected.chunks)
      db_.query("DELETE FROM chunks WHERE sha256 = ?1").bind(1, sha).run();
    return collected;
  });
}

namespace {

// The kinds of task whose output is a part of a frame that another task joins.
constexpr const char* kTileKinds = "(?2, ?3)";

}  // namespace

std::vector<std::string> FarmState::consumedTileOutputs(int64_t taskId) {
  // A tile's chunk may be named by several tasks (the same bytes): it goes when every task
  // naming it is a done tile whose readers are all done.
  const std::string sql = std::string(
      "SELECT DISTINCT t.output_sha FROM task_deps d JOIN tasks t ON t.id = d.depends_on "
      "WHERE d.task_id = ?1 AND t.kind IN ") + kTileKinds + " AND t.output_sha IS NOT NULL "
      "AND NOT EXISTS (SELECT 1 FROM tasks o WHERE o.output_sha = t.output_sha AND (o.state != ?4 OR o.kind NOT IN " +
      kTileKinds + " OR EXISTS (SELECT 1 FROM task_deps od JOIN tasks r ON r.id = od.task_id "
      "WHERE od.depends_on = o.id AND r.state != ?4)))";
  Statement& q = db_.query(sql);
  q.bind(1, taskId).bind(2, int64_t{TASK_RENDER_TILE}).bind(3, int64_t{TASK_GRADIENT_TILE}).bind(4, asInt(TaskState::Done));
  std::vector<std::string> shas;
  while (q.step()) shas.push_back(q.text(0));
  return shas;
}

std::vector<std::string> FarmState::takeReleasedTiles() {
  const std::lock_guard lock(releasedMutex_);
  return std::exchange(releasedTiles_, {});
}

}  // namespace pathfarm::farm
