// Large frames on the farm. A frame of more tiles than one assemble task may read
// (8-pixel tiles of a 520x520 frame: 4225) is assembled through regions, and comes out the
// frame a local render makes, bit for bit; a tile too large to check within a lease is
// accepted all the same.
#include "farm/farm_fixture.h"

namespace pathfarm::farmtest {
namespace {

// One square frame of `size` pixels in tiles of `tile`, at 1 spp.
RenderSpec squareFrame(const std::string& name, int size, int tile, int maxDepth) {
  RenderSpec spec;
  spec.name = name;
  spec.width = spec.height = size;
  spec.tile = tile;
  spec.spp = 1;
  spec.maxDepth = maxDepth;
  return spec;
}

TEST_F(FarmTest, AFrameOfManySmallTilesIsAssembledThroughRegions) {
  startScheduler();
  startWorker("w", {"--slots", "2"});
  const RenderSpec spec = squareFrame("many-tiles", 520, 8, 2);
  const int64_t id = client().submit(shotSpec(spec));
  const farm::ShotSummary summary = waitForShot(id, 110s);
  ASSERT_EQ(summary.state(), farm::SHOT_DONE) << describe(summary);
  EXPECT_EQ(summary.tasks_total(), 4225 + 2 + 1) << "4225 tiles, 2 regions, the frame";
  const FarmDatabase db = database();
  EXPECT_EQ(db.integer("SELECT COUNT(*) FROM tasks WHERE kind = 2 AND is_output = 0"), 2);
  expectSameFrames(fetchFrames(id, "fetched"), renderLocally(spec), spec);
}

// The scheduler checks an output before it answers the completion. A 2896x2896 tile takes
// longer to check than a lease of half a second lives; the worker renews the lease until
// the answer comes, so no lease expires and nothing runs twice. (Before, the lease expired
// during every check, the completion was refused and the tile rendered again forever.)
TEST_F(FarmTest, AnOutputWhoseCheckOutlastsTheLeaseIsAccepted) {
  SchedulerConfig config;
  config.leaseSeconds = 0.5;
  startScheduler(config);
  startWorker("w");
  const int64_t id = client().submit(shotSpec(squareFrame("one-large-tile", 2896, 2896, 1)));
  const farm::ShotSummary summary = waitForShot(id, 240s);
  ASSERT_EQ(summary.state(), farm::SHOT_DONE) << describe(summary);
  const FarmDatabase db = database();
  EXPECT_EQ(db.integer("SELECT COUNT(*) FROM attempts WHERE state != 1"), 0) << "an attempt did not end done";
  EXPECT_EQ(db.integer("SELECT COUNT(*) FROM attempts"), 2) << "the tile and the frame, once each";
}

}  // namespace
}  // namespace pathfarm::farmtest
