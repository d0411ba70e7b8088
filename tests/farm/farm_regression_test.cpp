// Regression tests for farm bugs found by the multi-process tests. Each states the bug.
#include "farm/farm_fixture.h"

namespace pathfarm::farmtest {
namespace {

// The worker's renderer cache once evicted by smallest shot id right after inserting, so
// a shot older than the two cached ones evicted itself and the worker crashed (SIGSEGV).
// Priorities make a worker take shots 2, 3, then 1.
TEST_F(FarmTest, WorkerTakesAnOlderShotAfterTwoNewerOnes) {
  startScheduler();
  std::vector<int64_t> ids;
  int priority[] = {0, 10, 5};
  for (int i = 0; i < 3; ++i) {
    RenderSpec spec;
    spec.name = "shot-" + std::to_string(i + 1);
    spec.width = spec.height = spec.tile = 32;
    spec.spp = 1;
    farm::ShotSpec shot = shotSpec(spec);
    shot.set_priority(priority[i]);
    ids.push_back(client().submit(shot));
  }
  farm::ChildProcess& solo = startWorker("solo");
  for (const int64_t id : ids) {
    ASSERT_TRUE(waitUntil(
        [&] { return solo.wait(0ms).has_value() || isOver(client().shot(id).summary().state()); }, 20s));
    ASSERT_FALSE(solo.wait(0ms).has_value()) << "the worker died:\n" << workerLog("solo");
    EXPECT_EQ(client().shot(id).summary().state(), farm::SHOT_DONE) << "shot " << id;
  }
}

// A worker is blocklisted for a shot after 3 failures (of any of its tasks), which can
// come before any one task has used its max_attempts: with one worker and a scene that
// cannot be loaded, the worker fails three tiles once each and is blocklisted. The shot
// once stayed SHOT_RUNNING for ever; now it fails, as no live worker may run it.
TEST_F(FarmTest, ShotWhoseWorkersAreAllBlocklistedStillEnds) {
  SchedulerConfig config;
  config.retryBackoffSeconds = 0.1;
  startScheduler(config);
  startWorker("solo");
  RenderSpec spec;
  spec.name = "four-broken-tiles";
  spec.width = spec.height = 64;
  spec.tile = 32;
  spec.maxAttempts = 3;
  farm::ShotSpec shot = shotSpec(spec);
  shot.set_scene((dir() / "missing_scene.json").string());
  const int64_t id = client().submit(shot);
  const farm::ShotSummary summary = waitForShot(id, 20s);
  EXPECT_EQ(summary.state(), farm::SHOT_FAILED) << describe(summary);
}

}  // namespace
}  // namespace pathfarm::farmtest
