// A scheduler and three workers render a small shot submitted, watched and fetched with
// the CLI; the frames are the bytes `pathfarm render` writes for the same settings.
#include "farm/farm_fixture.h"

namespace pathfarm::farmtest {
namespace {

TEST_F(FarmTest, ThreeWorkersRenderTheFramesThatRenderWritesLocally) {
  RenderSpec spec;
  spec.name = "three-workers";
  spec.frameStart = 3;  // not the scene's first frame: the frame number must reach the tiles
  spec.frameEnd = 5;
  spec.width = 64;
  spec.height = 48;  // tiles of 32: a full row and a cut-off row
  spec.spp = 4;
  spec.maxDepth = 4;
  spec.tile = 32;
  ASSERT_EQ(spec.tasks(), 15);

  const std::string scheduler = startScheduler();
  for (const char* name : {"w1", "w2", "w3"}) startWorker(name);

  const CommandResult submitted = runPathfarm({"submit", writeShotFile(spec).string(), "--scheduler", scheduler});
  ASSERT_EQ(submitted.status, 0) << submitted.output;
  const int64_t id = shotIdFrom(submitted);

  // `pathfarm watch` follows the shot to its end and exits 0 for a finished shot.
  const CommandResult watched = runPathfarm({"watch", std::to_string(id), "--scheduler", scheduler}, {}, 60s);
  ASSERT_EQ(watched.status, 0) << watched.output;
  EXPECT_TRUE(contains(watched.output, "SHOT_DONE")) << watched.output;

  const farm::ShotSummary summary = client().shot(id).summary();
  EXPECT_EQ(summary.state(), farm::SHOT_DONE) << describe(summary);
  EXPECT_EQ(summary.tasks_total(), spec.tasks());
  EXPECT_EQ(summary.tasks_done(), spec.tasks());
  EXPECT_EQ(summary.frames_done(), spec.frames());
  EXPECT_EQ(summary.tasks_failed(), 0);

  // Every task ran exactly once, and every attempt ended done (state 1).
  const FarmDatabase db = database();
  EXPECT_EQ(db.integer("SELECT COUNT(*) FROM attempts"), spec.tasks());
  EXPECT_EQ(db.integer("SELECT COUNT(*) FROM attempts WHERE state != 1"), 0);
  EXPECT_EQ(db.integer("SELECT COUNT(*) FROM tasks WHERE state != 3 OR output_sha IS NULL"), 0);

  const CommandResult status = runPathfarm({"status", std::to_string(id), "--scheduler", scheduler});
  EXPECT_EQ(status.status, 0) << status.output;
  EXPECT_TRUE(contains(status.output, "SHOT_DONE")) << status.output;

  // The report: a pt shot is its own baseline; an unknown shot is bad input.
  const CommandResult report = runPathfarm({"report", std::to_string(id), "--scheduler", scheduler, "--json"});
  EXPECT_EQ(report.status, 0) << report.output;
  EXPECT_TRUE(contains(report.output, "\"relative_cost\": 1")) << report.output;
  EXPECT_EQ(runPathfarm({"report", "999", "--scheduler", scheduler}).status, 2);

  const fs::path fetched = fetchFrames(id, "fetched");
  expectSameFrames(fetched, renderLocally(spec), spec);

  // Workers asked to stop (SIGTERM) finish and exit 0.
  for (const auto& [name, exitStatus] : stopWorkers()) EXPECT_EQ(exitStatus, 0) << "worker " << name;
}

TEST_F(FarmTest, AReferenceSharesNoSampleWithTheFramesItMeasures) {
  // A reference at the shot's own spp: were it drawn from the same samples as the output,
  // both would be the same image and the measured error exactly 0.
  RenderSpec spec;
  spec.name = "own-reference";
  spec.frameStart = spec.frameEnd = 2;
  spec.width = 32;
  spec.height = 24;
  spec.spp = 2;
  spec.maxDepth = 4;
  spec.tile = 32;
  farm::ShotSpec shot = shotSpec(spec);
  shot.set_reference_spp(spec.spp);
  shot.add_evaluation_frames(2);
  const std::string scheduler = startScheduler();
  startWorker("w1");
  const int64_t id = client().submit(shot);
  ASSERT_EQ(waitForShot(id, 60s).state(), farm::SHOT_DONE);
  const farm::ShotReport report = client().report(id);
  bool measured = false;
  for (const farm::StageError& error : report.errors()) {
    if (error.stage() != "final") continue;
    measured = true;
    EXPECT_GT(error.relmse(), 0) << "the reference repeated the output's samples";
  }
  EXPECT_TRUE(measured) << report.DebugString();
  EXPECT_GT(report.reference_noise(), 0);  // estimated from the reference's variance
}

}  // namespace
}  // namespace pathfarm::farmtest
