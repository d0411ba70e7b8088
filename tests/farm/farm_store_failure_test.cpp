// A scheduler whose store cannot take a worker's output (its disk failing): the worker
// sends the output a bounded number of times, then fails the attempt with the store's
// reason, so the shot ends FAILED with that reason instead of slots retrying forever or
// leases expiring one after the other.
#include "farm/farm_fixture.h"

namespace pathfarm::farmtest {
namespace {

TEST_F(FarmTest, AnOutputTheStoreCannotKeepFailsTheAttemptWithTheStoresReason) {
  SchedulerConfig config;
  config.retryBackoffSeconds = 0.1;
  startScheduler(config);
  RenderSpec spec;
  spec.name = "store-failing";
  spec.width = 32;
  spec.height = 32;
  spec.tile = 32;
  spec.maxAttempts = 2;
  const int64_t id = client().submit(shotSpec(spec));
  // Every folder a new chunk would go to is taken by a file: no chunk can be stored.
  const fs::path objects = storeFolder() / "objects";
  fs::create_directories(objects);
  const char* hex = "0123456789abcdef";
  for (int i = 0; i < 256; ++i) {
    const fs::path folder = objects / (std::string(1, hex[i / 16]) + hex[i % 16]);
    if (!fs::exists(folder)) writeFile(folder, "not a folder");
  }
  startWorker("w");

  const farm::ShotSummary summary = waitForShot(id, 60s);
  ASSERT_EQ(summary.state(), farm::SHOT_FAILED) << describe(summary);
  EXPECT_TRUE(contains(summary.failure(), "cannot upload its output")) << summary.failure();
  EXPECT_TRUE(contains(summary.failure(), "cannot store chunk")) << summary.failure();
  EXPECT_EQ(database().integer("SELECT COUNT(*) FROM attempts WHERE state = 3"), 0) << "no lease had to expire";
}

}  // namespace
}  // namespace pathfarm::farmtest
