// Crashes: a worker killed in the middle of a tile, and the scheduler killed in the
// middle of a shot. The farm finishes either way, redoes only what was lost, and the
// frames are still the bytes `pathfarm render` writes.
#include <map>
#include <tuple>

#include "farm/farm_fixture.h"

namespace pathfarm::farmtest {
namespace {

TEST_F(FarmTest, KilledWorkersLeaseExpiresAndAnotherWorkerRedoesItsTile) {
  // Two tiles of 64x64 at 384 spp: about 1.5 s each on one thread, long enough to kill
  // a worker inside one; 32-pixel render blocks make the progress move within a tile.
  RenderSpec spec;
  spec.name = "killed-worker";
  spec.frameStart = spec.frameEnd = 7;
  spec.width = 128;
  spec.height = 64;
  spec.tile = 64;
  spec.spp = 384;
  spec.maxDepth = 4;
  ASSERT_EQ(spec.tasks(), 3);

  SchedulerConfig config;
  config.leaseSeconds = 0.6;  // heartbeats every 0.2 s; a tile takes about 1 s
  startScheduler(config);
  const int64_t id = client().submit(shotSpec(spec));
  farm::ChildProcess& victim = startWorker("victim");
  startWorker("survivor");

  // Mid-task: the victim holds a running lease (state 0) on a tile and has reported
  // progress on it, but not all of it.
  const FarmDatabase db = database();
  std::vector<std::vector<std::string>> running;
  ASSERT_TRUE(waitUntil(
      [&] {
        running = db.rows(
            "SELECT a.id, a.task_id, a.progress FROM attempts a JOIN workers w ON w.id = a.worker_id "
            "JOIN tasks t ON t.id = a.task_id WHERE w.name = 'victim' AND a.state = 0 AND t.kind = 1 "
            "AND a.progress > 0 AND a.progress < 1");
        return !running.empty();
      },
      20s))
      << "the victim never reported progress inside a tile";
  const std::string attempt = running[0][0], task = running[0][1];
  victim.signal(SIGKILL);
  ASSERT_EQ(victim.wait(5s), 128 + SIGKILL);

  const farm::ShotSummary summary = waitForShot(id, 40s);
  ASSERT_EQ(summary.state(), farm::SHOT_DONE) << describe(summary);

  // The victim's attempt ended by expiry (state 3), not by a report...
  const auto victimAttempt = db.rows("SELECT state, error FROM attempts WHERE id = " + attempt);
  ASSERT_EQ(victimAttempt.size(), 1u);
  EXPECT_EQ(victimAttempt[0][0], "3") << "attempt " << attempt << " error: " << victimAttempt[0][1];
  EXPECT_TRUE(contains(victimAttempt[0][1], "expired")) << victimAttempt[0][1];
  // ...and the survivor did the tile: one later attempt, done (state 1).
  const auto redone = db.rows("SELECT a.id, w.name FROM attempts a JOIN workers w ON w.id = a.worker_id "
                              "WHERE a.task_id = " + task + " AND a.state = 1");
  ASSERT_EQ(redone.size(), 1u) << "task " << task << " should have been done exactly once";
  EXPECT_EQ(redone[0][1], "survivor");
  EXPECT_GT(std::stoll(redone[0][0]), std::stoll(attempt));
  EXPECT_EQ(db.integer("SELECT state FROM tasks WHERE id = " + task), 3);
  EXPECT_EQ(summary.attempts(), db.integer("SELECT COUNT(*) FROM attempts"));
  // Only the victim's lease ran out: the survivor's heartbeats kept each of its own,
  // though its tiles outlasted a lease.
  EXPECT_EQ(db.integer("SELECT COUNT(*) FROM attempts WHERE state = 3"), 1);
  EXPECT_GT(db.integer("SELECT COUNT(*) FROM attempts a JOIN workers w ON w.id = a.worker_id "
                       "WHERE w.name = 'survivor' AND a.state = 1 AND a.finished_at - a.leased_at > 0.6"),
            0);

  const fs::path fetched = fetchFrames(id, "fetched");
  expectSameFrames(fetched, renderLocally(spec), spec);
}

// Workers told to stop (SIGTERM) in the middle of a tile: one whose notice is short
// (--hand-back-after 0, a preempted node) abandons its tile, hands it back and exits, and
// the next worker takes it at once, long before the lease would have run out; one with
// the default grace finishes and delivers its tile. Nobody is charged a failure.
TEST_F(FarmTest, AStoppedWorkerHandsBackATaskThatOutlastsItsGraceAndDeliversOneThatDoesNot) {
  // Three tiles of about 1.3 s each on one thread here (768 spp took 0.48 s by 2026-12-04,
  // and a tile could end before the stop 300 ms into it reached its worker).
  RenderSpec spec;
  spec.name = "stopped-workers";
  spec.frameStart = spec.frameEnd = 7;
  spec.width = 192;
  spec.height = 64;
  spec.tile = 64;
  spec.spp = 2048;
  spec.maxDepth = 4;

  SchedulerConfig config;
  config.leaseSeconds = 30;  // what a vanished worker would cost
  startScheduler(config);
  const int64_t id = client().submit(shotSpec(spec));
  const FarmDatabase db = database();
  // Starts a worker, waits until it is inside a tile, stops it; returns the tile's attempt
  // and task.
  const auto stopInsideATile = [&](const std::string& name, const std::vector<std::string>& arguments) {
    farm::ChildProcess& worker = startWorker(name, arguments);
    std::vector<std::vector<std::string>> running;
    const bool leased = waitUntil(
        [&] {
          running = db.rows("SELECT a.id, a.task_id FROM attempts a JOIN workers w ON w.id = a.worker_id "
                            "JOIN tasks t ON t.id = a.task_id WHERE w.name = '" + name + "' AND a.state = 0 AND t.kind = 1");
          return !running.empty();
        },
        20s);
    if (!leased) throw std::runtime_error(name + " never leased a tile");
    std::this_thread::sleep_for(300ms);  // inside the tile; a 30-s lease sends no progress yet
    worker.signal(SIGTERM);
    if (worker.wait(20s) != 0) throw std::runtime_error(name + " did not exit 0 after SIGTERM");
    return running[0];
  };
  const std::vector<std::string> handed = stopInsideATile("preempted", {"--hand-back-after", "0"});
  const std::vector<std::string> delivered = stopInsideATile("drained", {});
  startWorker("survivor");

  const farm::ShotSummary summary = waitForShot(id, 20s);
  ASSERT_EQ(summary.state(), farm::SHOT_DONE) << describe(summary);
  const auto handedBack = db.rows("SELECT state, failure_class FROM attempts WHERE id = " + handed[0]);
  ASSERT_EQ(handedBack.size(), 1u);
  EXPECT_EQ(handedBack[0][0], "2");  // ended by the worker's report, not by expiry (3) or as done (1)
  EXPECT_EQ(handedBack[0][1], "released");
  EXPECT_EQ(db.integer("SELECT lost FROM tasks WHERE id = " + handed[1]), 1);
  EXPECT_EQ(db.integer("SELECT state FROM attempts WHERE id = " + delivered[0]), 1);
  EXPECT_EQ(db.integer("SELECT COALESCE(SUM(failures), 0) FROM tasks"), 0);
  const auto redone = db.rows("SELECT w.name FROM attempts a JOIN workers w ON w.id = a.worker_id "
                              "WHERE a.task_id = " + handed[1] + " AND a.state = 1");
  ASSERT_EQ(redone.size(), 1u);
  EXPECT_NE(redone[0][0], "preempted");

  const fs::path fetched = fetchFrames(id, "fetched");
  expectSameFrames(fetched, renderLocally(spec), spec);
}

TEST_F(FarmTest, SchedulerKilledMidShotRestartsOnItsDatabaseWithoutRedoingFinishedTasks) {
  // 12 tiles of 32x32 at 256 spp (about a quarter second each) and 3 assemblies.
  RenderSpec spec;
  spec.name = "killed-scheduler";
  spec.frameStart = 10;
  spec.frameEnd = 12;
  spec.width = 64;
  spec.height = 64;
  spec.tile = 32;
  spec.spp = 256;
  spec.maxDepth = 4;
  ASSERT_EQ(spec.tasks(), 15);

  SchedulerConfig config;
  config.leaseSeconds = 5;
  startScheduler(config);
  const int64_t id = client().submit(shotSpec(spec));
  startWorker("w1");
  startWorker("w2");

  // Some tasks done, not all: read what is done, then kill the scheduler outright.
  const FarmDatabase db = database();
  ASSERT_TRUE(waitUntil([&] { return db.integer("SELECT COUNT(*) FROM tasks WHERE state = 3") >= 3; }, 30s))
      << "the farm did not finish 3 tasks";
  // task -> (attempts, output digest) for every task done before the kill.
  std::map<std::string, std::tuple<std::string, std::string>> doneBefore;
  for (const auto& row : db.rows("SELECT t.id, (SELECT COUNT(*) FROM attempts a WHERE a.task_id = t.id), "
                                 "t.output_sha FROM tasks t WHERE t.state = 3"))
    doneBefore[row[0]] = {row[1], row[2]};
  killScheduler();
  ASSERT_GE(doneBefore.size(), 3u);
  ASSERT_LT(doneBefore.size(), static_cast<size_t>(spec.tasks())) << "the shot ended before the scheduler was killed";

  // The same database, store and port: the workers that kept running reconnect.
  const int oldPort = port();
  config.listen = "127.0.0.1:" + std::to_string(oldPort);
  startScheduler(config);
  ASSERT_EQ(port(), oldPort);

  const farm::ShotSummary summary = waitForShot(id, 60s);
  ASSERT_EQ(summary.state(), farm::SHOT_DONE) << describe(summary);
  EXPECT_EQ(summary.tasks_done(), spec.tasks());

  // No task done before the kill got another attempt, or another output.
  for (const auto& [task, before] : doneBefore) {
    const auto after = db.rows("SELECT t.state, (SELECT COUNT(*) FROM attempts a WHERE a.task_id = t.id), "
                               "t.output_sha FROM tasks t WHERE t.id = " + task);
    ASSERT_EQ(after.size(), 1u);
    EXPECT_EQ(after[0][0], "3") << "task " << task;
    EXPECT_EQ(after[0][1], std::get<0>(before)) << "task " << task << " was attempted again after the restart";
    EXPECT_EQ(after[0][2], std::get<1>(before)) << "task " << task << " changed its output";
  }
  // The restarted scheduler still has the chunks the first one stored: the files, but for
  // the tiles, which leave the store once their frame is assembled (their rows stay).
  for (const auto& [task, before] : doneBefore) {
    const std::string& sha = std::get<1>(before);
    EXPECT_EQ(db.integer("SELECT COUNT(*) FROM chunks WHERE sha256 = '" + sha + "'"), 1) << "task " << task;
    if (db.integer("SELECT kind FROM tasks WHERE id = " + task) != farm::TASK_RENDER_TILE)
      EXPECT_TRUE(fs::exists(chunkFile(sha))) << "task " << task << "'s output chunk";
  }

  const fs::path fetched = fetchFrames(id, "fetched");
  expectSameFrames(fetched, renderLocally(spec), spec);
}

}  // namespace
}  // namespace pathfarm::farmtest
