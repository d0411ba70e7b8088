// A shot whose task fails on every attempt: it ends SHOT_FAILED with the reason, the
// workers that failed it keep running and keep working, and once the cause is mended
// `pathfarm retry` finishes it. A scene no worker can read fails its shot as soon as two
// workers have said so.
#include "farm/farm_fixture.h"

namespace pathfarm::farmtest {
namespace {

TEST_F(FarmTest, ShotFailingEveryAttemptEndsFailedWithItsReasonAndWorkersSurvive) {
  SchedulerConfig config;
  config.retryBackoffSeconds = 0.1;
  const std::string scheduler = startScheduler(config);
  startWorker("worker-a");
  startWorker("worker-b");

  // Submitted with FarmClient, past the CLI's check that the scene exists: one tile,
  // two attempts allowed, each fails loading the scene.
  RenderSpec spec;
  spec.name = "broken-scene";
  spec.width = 32;
  spec.height = 32;
  spec.tile = 32;
  spec.maxAttempts = 2;
  const fs::path missingScene = dir() / "nowhere" / "missing_scene.json";
  farm::ShotSpec shot = shotSpec(spec);
  shot.set_scene(missingScene.string());
  const int64_t id = client().submit(shot);

  const farm::ShotSummary summary = waitForShot(id, 30s);
  ASSERT_EQ(summary.state(), farm::SHOT_FAILED) << describe(summary);
  EXPECT_TRUE(contains(summary.failure(), missingScene.string())) << summary.failure();
  EXPECT_EQ(summary.tasks_failed(), 1);

  // Exactly the two attempts allowed, both failed (state 2) on the scene file.
  const FarmDatabase db = database();
  EXPECT_EQ(db.integer("SELECT COUNT(*) FROM attempts"), 2);
  for (const auto& row : db.rows("SELECT state, error FROM attempts")) {
    EXPECT_EQ(row[0], "2");
    EXPECT_TRUE(contains(row[1], "missing_scene.json")) << row[1];
  }
  EXPECT_EQ(db.integer("SELECT failures FROM tasks WHERE kind = 1"), 2);
  EXPECT_EQ(db.integer("SELECT state FROM tasks WHERE kind = 1"), 4);

  // `pathfarm status ID` shows the state and why.
  const CommandResult status = runPathfarm({"status", std::to_string(id), "--scheduler", scheduler});
  EXPECT_EQ(status.status, 0) << status.output;
  EXPECT_TRUE(contains(status.output, "SHOT_FAILED")) << status.output;
  EXPECT_TRUE(contains(status.output, "failure:")) << status.output;
  EXPECT_TRUE(contains(status.output, missingScene.string())) << status.output;
  // `pathfarm watch` of a failed shot exits 1.
  const CommandResult watched = runPathfarm({"watch", std::to_string(id), "--scheduler", scheduler});
  EXPECT_EQ(watched.status, 1) << watched.output;

  // Both workers are alive, listed, and still render: a good shot completes after.
  std::this_thread::sleep_for(300ms);  // a worker that was going to die of it has had time to
  for (const char* name : {"worker-a", "worker-b"})
    EXPECT_FALSE(worker(name).wait(0ms).has_value()) << name << " exited:\n" << workerLog(name);
  const CommandResult workers = runPathfarm({"workers", "--scheduler", scheduler});
  EXPECT_EQ(workers.status, 0) << workers.output;
  EXPECT_TRUE(contains(workers.output, " worker-a: ")) << workers.output;
  EXPECT_TRUE(contains(workers.output, " worker-b: ")) << workers.output;

  RenderSpec good;
  good.name = "after-the-failure";
  good.width = 32;
  good.height = 32;
  good.tile = 16;
  const int64_t next = client().submit(shotSpec(good));
  const farm::ShotSummary after = waitForShot(next, 30s);
  EXPECT_EQ(after.state(), farm::SHOT_DONE) << describe(after);
  EXPECT_EQ(client().shot(id).summary().state(), farm::SHOT_FAILED);

  // The scene turns up: `pathfarm retry` runs the failed shot again and it finishes.
  fs::create_directories(missingScene.parent_path());
  fs::copy_file(cornellScene(), missingScene);
  const CommandResult retried = runPathfarm({"retry", std::to_string(id), "--scheduler", scheduler});
  EXPECT_EQ(retried.status, 0) << retried.output;
  EXPECT_TRUE(contains(retried.output, "SHOT_RUNNING")) << retried.output;
  const farm::ShotSummary mended = waitForShot(id, 30s);
  EXPECT_EQ(mended.state(), farm::SHOT_DONE) << describe(mended);
  EXPECT_EQ(mended.frames_done(), 1);
}

TEST_F(FarmTest, AMalformedSceneFailsItsShotWithoutBlamingAWorker) {
  SchedulerConfig config;
  config.retryBackoffSeconds = 0.1;
  startScheduler(config);
  startWorker("worker-a");
  startWorker("worker-b");

  // Past the CLI's checks: the scene file exists but is not a scene.
  const fs::path scene = dir() / "malformed_scene.json";
  writeFile(scene, R"({"camera": {"position": [0, 1e400, 0]}})");
  RenderSpec spec;
  spec.name = "malformed-scene";
  spec.width = 32;
  spec.height = 32;
  spec.tile = 32;
  spec.maxAttempts = 3;
  farm::ShotSpec shot = shotSpec(spec);
  shot.set_scene(scene.string());
  const int64_t id = client().submit(shot);

  // Failed once a second worker found the scene bad too (or, should one worker lease it
  // every time, after its 3 attempts).
  const farm::ShotSummary summary = waitForShot(id, 30s);
  ASSERT_EQ(summary.state(), farm::SHOT_FAILED) << describe(summary);
  EXPECT_TRUE(contains(summary.failure(), "malformed_scene.json")) << summary.failure();
  const FarmDatabase db = database();
  const int64_t attempts = db.integer("SELECT COUNT(*) FROM attempts");
  EXPECT_TRUE(attempts == 2 || attempts == 3) << attempts;
  EXPECT_EQ(db.integer("SELECT COUNT(*) FROM attempts WHERE failure_class = 'bad_input'"), attempts);
  if (db.integer("SELECT COUNT(DISTINCT worker_id) FROM attempts") == 2) {
    EXPECT_TRUE(contains(summary.failure(), "bad input")) << summary.failure();
  }
  EXPECT_EQ(db.integer("SELECT COUNT(*) FROM worker_failures"), 0) << "a worker was blamed for the scene";
}

}  // namespace
}  // namespace pathfarm::farmtest
