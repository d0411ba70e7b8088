// A frame of more tiles than one assemble task may read (8-pixel tiles of a 520x520
// frame: 4225) is assembled through regions on the farm, and comes out the frame a local
// render makes, bit for bit.
#include "farm/farm_fixture.h"

namespace pathfarm::farmtest {
namespace {

TEST_F(FarmTest, AFrameOfManySmallTilesIsAssembledThroughRegions) {
  startScheduler();
  startWorker("w", {"--slots", "2"});
  RenderSpec spec;
  spec.name = "many-tiles";
  spec.width = 520;
  spec.height = 520;
  spec.tile = 8;
  spec.spp = 1;
  spec.maxDepth = 2;
  const int64_t id = client().submit(shotSpec(spec));
  const farm::ShotSummary summary = waitForShot(id, 110s);
  ASSERT_EQ(summary.state(), farm::SHOT_DONE) << describe(summary);
  EXPECT_EQ(summary.tasks_total(), 4225 + 2 + 1) << "4225 tiles, 2 regions, the frame";
  const FarmDatabase db = database();
  EXPECT_EQ(db.integer("SELECT COUNT(*) FROM tasks WHERE kind = 2 AND is_output = 0"), 2);
  expectSameFrames(fetchFrames(id, "fetched"), renderLocally(spec), spec);
}

}  // namespace
}  // namespace pathfarm::farmtest
