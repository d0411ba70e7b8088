// FarmState's retention: finished shots past settings().retainSeconds are deleted, and the
// chunks nothing kept needs any more; intermediate chunks go from the store once read.
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

std::vector<std::string> FarmState::releaseConsumedInputs(int64_t taskId) {
  if (settings_.keepIntermediates) return {};
  // A chunk may be named by several tasks (the same bytes): it goes when every task naming
  // it is done, none is a shot's frame, and all their readers are done.
  Statement& candidates = db_.query(
      "SELECT DISTINCT t.output_sha FROM task_deps d JOIN tasks t ON t.id = d.depends_on "
      "WHERE d.task_id = ?1 AND t.output_sha IS NOT NULL "
      "AND NOT EXISTS (SELECT 1 FROM tasks o WHERE o.output_sha = t.output_sha AND (o.state != ?2 OR o.is_output = 1 "
      "OR EXISTS (SELECT 1 FROM task_deps od JOIN tasks r ON r.id = od.task_id WHERE od.depends_on = o.id AND r.state != ?2)))");
  candidates.bind(1, taskId).bind(2, asInt(TaskState::Done));
  std::vector<std::string> shas;
  while (candidates.step()) shas.push_back(candidates.text(0));
  candidates.reset();
  // References outlive their shot: a later shot of the same scene reuses them.
  const auto namesAReference = [&](const std::string& sha) {
    Statement& q = db_.query("SELECT params FROM tasks WHERE output_sha = ?1 AND kind = ?2");
    q.bind(1, sha).bind(2, int64_t{TASK_ASSEMBLE_FRAME});
    bool reference = false;
    while (q.step()) {
      TaskParams params;
      params.ParseFromString(q.blob(0));
      reference = reference || params.role() == ROLE_REFERENCE;
    }
    return reference;
  };
  std::erase_if(shas, namesAReference);
  for (const std::string& sha : shas)
    db_.query("UPDATE chunks SET released = 1 WHERE sha256 = ?1").bind(1, sha).run();
  return shas;
}

std::vector<std::string> FarmState::releasedChunks() {
  return transact([&] {
    std::vector<std::string> shas;
    Statement& released = db_.query("SELECT sha256 FROM chunks WHERE released = 1");
    while (released.step()) shas.push_back(released.text(0));
    released.reset();
    return shas;
  });
}

std::vector<std::string> FarmState::takeReleasedChunks() {
  const std::lock_guard lock(releasedMutex_);
  return std::exchange(releasedChunks_, {});
}

}  // namespace pathfarm::farm
