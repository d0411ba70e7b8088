// A worker whose scheduler forgot its session (restarted on a fresh database) registers
// again once for the whole process, however many slots it runs, and goes on working.
#include "farm/farm_fixture.h"

namespace pathfarm::farmtest {
namespace {

TEST_F(FarmTest, AWorkerWithSeveralSlotsRegistersAgainOnceWhenItsSessionIsForgotten) {
  SchedulerConfig config;
  startScheduler(config);
  startWorker("w", {"--slots", "3"});
  {
    const FarmDatabase db = database();
    ASSERT_TRUE(waitUntil([&] { return db.integer("SELECT COUNT(*) FROM workers") == 1; }, 15s));
  }
  // The scheduler dies and comes back on the same port with no database: every slot's
  // next lease is refused for its unknown session.
  const int oldPort = port();
  killScheduler();
  for (const char* suffix : {"", "-wal", "-shm"}) fs::remove(databaseFile().string() + suffix);
  config.listen = "127.0.0.1:" + std::to_string(oldPort);
  startScheduler(config);

  RenderSpec spec;
  spec.name = "after-a-fresh-database";
  spec.frameEnd = 1;
  const int64_t id = client().submit(shotSpec(spec));
  const farm::ShotSummary summary = waitForShot(id, 60s);
  ASSERT_EQ(summary.state(), farm::SHOT_DONE) << describe(summary);
  const FarmDatabase db = database();
  EXPECT_EQ(db.integer("SELECT COUNT(*) FROM workers"), 1) << "each slot registered on its own";
  EXPECT_EQ(db.integer("SELECT COUNT(DISTINCT worker_id) FROM attempts"), 1);
  expectSameFrames(fetchFrames(id, "fetched"), renderLocally(spec), spec);
}

}  // namespace
}  // namespace pathfarm::farmtest
