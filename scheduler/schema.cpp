#include "scheduler/schema.h"

#include <string>
#include <vector>

#include "contract/pipeline.h"
#include "pathfarm/shot.pb.h"

namespace pathfarm::farm {
namespace {

// Append only: a released migration never changes, a new one is added at the end.
const std::vector<const char*>& migrations() {
  static const std::vector<const char*> list = {
      // 1: the farm's first schema.
      R"sql(
      CREATE TABLE shots (
        id INTEGER PRIMARY KEY,
        name TEXT NOT NULL,
        spec BLOB NOT NULL,                -- ShotSpec, serialized
        state INTEGER NOT NULL,            -- ShotState
        priority INTEGER NOT NULL,
        tasks_left INTEGER NOT NULL,       -- tasks not yet done: the shot is done at 0
        submitted_at REAL NOT NULL,
        started_at REAL,
        finished_at REAL,
        failure TEXT NOT NULL DEFAULT '');
      CREATE TABLE chunks (
        sha256 TEXT PRIMARY KEY,
        size INTEGER NOT NULL,
        stored_at REAL NOT NULL);
      CREATE TABLE tasks (
        id INTEGER PRIMARY KEY,
        shot_id INTEGER NOT NULL REFERENCES shots(id) ON DELETE CASCADE,
        kind INTEGER NOT NULL,             -- TaskKind
        params BLOB NOT NULL,              -- TaskParams, serialized
        state INTEGER NOT NULL,            -- TaskState
        pending_deps INTEGER NOT NULL,     -- dependencies not yet done
        failures INTEGER NOT NULL DEFAULT 0,
        max_attempts INTEGER NOT NULL,
        not_before REAL NOT NULL DEFAULT 0,  -- retry backoff
        attempt_id INTEGER,                -- the current lease
        output_sha TEXT REFERENCES chunks(sha256));
      CREATE INDEX tasks_by_shot ON tasks(shot_id, state, id);
      CREATE TABLE task_deps (
        task_id INTEGER NOT NULL REFERENCES tasks(id) ON DELETE CASCADE,
        depends_on INTEGER NOT NULL REFERENCES tasks(id) ON DELETE CASCADE,
        PRIMARY KEY (task_id, depends_on));
      CREATE INDEX task_deps_reverse ON task_deps(depends_on);
      CREATE TABLE workers (
        id INTEGER PRIMARY KEY,
        name TEXT NOT NULL,
        slots INTEGER NOT NULL,
        registered_at REAL NOT NULL,
        last_seen REAL NOT NULL);
      CREATE TABLE attempts (
        id INTEGER PRIMARY KEY,
        task_id INTEGER NOT NULL REFERENCES tasks(id) ON DELETE CASCADE,
        worker_id INTEGER NOT NULL REFERENCES workers(id),
        state INTEGER NOT NULL,            -- AttemptState
        leased_at REAL NOT NULL,
        expires_at REAL NOT NULL,
        progress REAL NOT NULL DEFAULT 0,
        progress_at REAL NOT NULL,
        finished_at REAL,
        error TEXT NOT NULL DEFAULT '');
      CREATE INDEX attempts_by_state ON attempts(state, expires_at);
      CREATE INDEX attempts_by_task ON attempts(task_id);
      CREATE TABLE worker_failures (
        shot_id INTEGER NOT NULL REFERENCES shots(id) ON DELETE CASCADE,
        worker_id INTEGER NOT NULL REFERENCES workers(id),
        failures INTEGER NOT NULL,
        blocklisted INTEGER NOT NULL DEFAULT 0,
        PRIMARY KEY (shot_id, worker_id));
      CREATE TABLE events (
        id INTEGER PRIMARY KEY,
        shot_id INTEGER REFERENCES shots(id) ON DELETE CASCADE,
        time REAL NOT NULL,
        message TEXT NOT NULL);
      CREATE INDEX events_by_shot ON events(shot_id, id);
      )sql",
      // 2: filtering pipelines: frame outputs other than assembled tiles, tasks created
      // while a shot runs, and the figures of the speed-against-error report.
      R"sql(
      ALTER TABLE tasks ADD COLUMN is_output INTEGER NOT NULL DEFAULT 0;  -- one of the shot's frames
      UPDATE tasks SET is_output = 1 WHERE kind = 2;
      ALTER TABLE tasks ADD COLUMN core_seconds REAL NOT NULL DEFAULT 0;  -- of the accepted attempt
      CREATE TABLE task_metrics (
        task_id INTEGER NOT NULL REFERENCES tasks(id) ON DELETE CASCADE,
        name TEXT NOT NULL,
        value REAL NOT NULL,
        PRIMARY KEY (task_id, name));
      )sql",
      // 3: attempts whose worker vanished (a lease that expired) are counted apart from
      // failures: a lost node is not the task's fault.
      R"sql(
      ALTER TABLE tasks ADD COLUMN lost INTEGER NOT NULL DEFAULT 0;
      )sql",
      // 4: a submit names itself, so that a retried submit returns the shot it made.
      R"sql(
      ALTER TABLE shots ADD COLUMN submit_key TEXT;
      CREATE UNIQUE INDEX shots_by_submit_key ON shots(submit_key) WHERE submit_key IS NOT NULL;
      )sql",
      // 5: pools. Tags as ",a,b," (empty: none); a shot's cap on workers (0: none).
      R"sql(
      ALTER TABLE workers ADD COLUMN tags TEXT NOT NULL DEFAULT '';
      ALTER TABLE shots ADD COLUMN required_tags TEXT NOT NULL DEFAULT '';
      ALTER TABLE shots ADD COLUMN max_workers INTEGER NOT NULL DEFAULT 0;
      )sql",
      // 6: a re-render tile remembers the task that asked for it, so that requeueing that
      // task drops the tile (the task asks again when it runs).
      R"sql(
      ALTER TABLE tasks ADD COLUMN created_by INTEGER REFERENCES tasks(id) ON DELETE CASCADE;
      )sql",
      // 7: a worker's session key (SHA-256 hex of it): only that worker may report on its
      // attempts. Empty for workers registered before.
      R"sql(
      ALTER TABLE workers ADD COLUMN session_hash TEXT NOT NULL DEFAULT '';
      )sql",
      // 8: the tail of what the worker logged while it ran the attempt (the dashboard's
      // per-task log). Empty for attempts reported before.
      R"sql(
      ALTER TABLE attempts ADD COLUMN log_tail TEXT NOT NULL DEFAULT '';
      )sql",
      // 9: whose fault a failed attempt was, as the worker reported it: "worker_fault",
      // "bad_input" or "transport". Empty for attempts that did not fail or ended before.
      // And the tasks that name a chunk, found without a scan (retention).
      R"sql(
      ALTER TABLE attempts ADD COLUMN failure_class TEXT NOT NULL DEFAULT '';
      CREATE INDEX tasks_by_output ON tasks(output_sha) WHERE output_sha IS NOT NULL;
      )sql",
      // 10: a shot whose tasks are still being inserted, a batch per transaction (1): none
      // of them is leased yet. And the re-render tiles a task made, found without a scan:
      // deleting a shot's tasks checks each for tiles it made (ON DELETE CASCADE).
      R"sql(
      ALTER TABLE shots ADD COLUMN building INTEGER NOT NULL DEFAULT 0;
      CREATE INDEX tasks_by_creator ON tasks(created_by) WHERE created_by IS NOT NULL;
      )sql",
      // 11: re-render tiles a running attempt asked for, in batches, until it completes
      // (they become tasks) or ends otherwise (they are dropped).
      R"sql(
      CREATE TABLE follow_ups (
        id INTEGER PRIMARY KEY,
        attempt_id INTEGER NOT NULL REFERENCES attempts(id) ON DELETE CASCADE,
        params BLOB NOT NULL               -- TaskParams of a render tile, serialized
      );
      CREATE INDEX follow_ups_by_attempt ON follow_ups(attempt_id);
      )sql",
      // 12: a shot's pipeline is a Pipeline, no longer a name (moveLegacyPipelineNames).
      "",
      // 13: shots a shot waits for (ShotSpec::after_shots), and the shots waiting for one.
      R"sql(
      CREATE TABLE shot_waits (
        shot_id INTEGER NOT NULL REFERENCES shots(id) ON DELETE CASCADE,
        after_id INTEGER NOT NULL REFERENCES shots(id) ON DELETE CASCADE,
        PRIMARY KEY (shot_id, after_id));
      CREATE INDEX shot_waits_reverse ON shot_waits(after_id);
      )sql",
      // 14: a chunk whose file the scheduler removed once no task read it any more
      // (FarmState::takeReleasedChunks); stored again, it is kept again.
      R"sql(
      ALTER TABLE chunks ADD COLUMN released INTEGER NOT NULL DEFAULT 0;
      )sql",
  };
  return list;
}

// Schema 12: every stored spec's pipeline name becomes its Pipeline value. A name no
// pipeline has (none could be submitted) stays PIPELINE_UNSPECIFIED, which the planner
// and workers refuse with a message.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"  // the legacy field is read here and only here
void moveLegacyPipelineNames(Database& db) {
  std::vector<std::pair<int64_t, std::string>> rewritten;
  Statement& shots = db.query("SELECT id, spec FROM shots");
  while (shots.step()) {
    ShotSpec spec;
    spec.ParseFromString(shots.blob(1));
    if (spec.legacy_pipeline_name().empty()) continue;
    spec.set_pipeline(pipelineNamed(spec.legacy_pipeline_name()).value_or(PIPELINE_UNSPECIFIED));
    spec.clear_legacy_pipeline_name();
    rewritten.emplace_back(shots.integer(0), spec.SerializeAsString());
  }
  shots.reset();
  for (const auto& [id, blob] : rewritten) {
    Statement& update = db.query("UPDATE shots SET spec = ?1 WHERE id = ?2");
    update.bindBlob(1, blob).bind(2, id).step();
    update.reset();
  }
}
#pragma GCC diagnostic pop

}  // namespace

int schemaVersion(Database& db) {
  Statement& statement = db.query("PRAGMA user_version");
  statement.step();
  const int version = static_cast<int>(statement.integer(0));
  statement.reset();
  return version;
}

void migrate(Database& db, int upTo) {
  const int newest = upTo > 0 ? upTo : static_cast<int>(migrations().size());
  const int current = schemaVersion(db);
  if (current > newest)
    throw DatabaseError("the database has schema version " + std::to_string(current) +
                        ", newer than this pathfarm understands (" + std::to_string(newest) + ")");
  for (int version = current; version < newest; ++version) {
    Transaction transaction(db);
    db.execute(migrations()[static_cast<size_t>(version)]);
    if (version + 1 == 12) moveLegacyPipelineNames(db);
    db.execute("PRAGMA user_version = " + std::to_string(version + 1));
    transaction.commit();
  }
}

}  // namespace pathfarm::farm
