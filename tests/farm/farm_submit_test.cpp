// A submit repeated with its key (a script retrying `pathfarm submit` after a timeout)
// prints the same shot and queues nothing more; without a key each submit is a shot.
// After submission the shot's priority changes and the blocklist is listed by the CLI.
#include "farm/farm_fixture.h"

namespace pathfarm::farmtest {
namespace {

TEST_F(FarmTest, ASubmitRepeatedWithItsKeyMakesOneShot) {
  const std::string scheduler = startScheduler();
  RenderSpec spec;
  spec.name = "keyed";
  const std::string shotFile = writeShotFile(spec).string();
  const auto submit = [&](std::vector<std::string> extra) {
    std::vector<std::string> arguments = {"submit", shotFile, "--scheduler", scheduler};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    const CommandResult result = runPathfarm(arguments);
    EXPECT_EQ(result.status, 0) << result.output;
    return shotIdFrom(result);
  };
  const int64_t first = submit({"--submit-key", "render-42"});
  EXPECT_EQ(submit({"--submit-key", "render-42"}), first);
  EXPECT_EQ(client().shots().size(), 1u);
  EXPECT_NE(submit({}), first);
  EXPECT_EQ(client().shots().size(), 2u);
  EXPECT_EQ(database().integer("SELECT COUNT(*) FROM tasks WHERE shot_id = " + std::to_string(first)), spec.tasks());

  // The controls an operator has after submission.
  const CommandResult raised = runPathfarm({"priority", std::to_string(first), "7", "--scheduler", scheduler});
  EXPECT_EQ(raised.status, 0) << raised.output;
  EXPECT_TRUE(contains(raised.output, ", priority 7")) << raised.output;
  EXPECT_EQ(client().shot(first).summary().priority(), 7);
  const CommandResult listed = runPathfarm({"blocklist", "--scheduler", scheduler});
  EXPECT_EQ(listed.status, 0) << listed.output;
  EXPECT_TRUE(contains(listed.output, "no worker is blocklisted")) << listed.output;
  const CommandResult cleared = runPathfarm({"blocklist", "--clear", "--scheduler", scheduler});
  EXPECT_NE(cleared.status, 0) << cleared.output;
  EXPECT_TRUE(contains(cleared.output, "--clear needs a shot id")) << cleared.output;
}

TEST_F(FarmTest, AShotRequiringTagsRunsOnlyOnWorkersCarryingThem) {
  startScheduler();
  startWorker("plain");
  startWorker("tagged", {"--tags", "gpu,big"});
  RenderSpec spec;
  spec.name = "pooled";
  spec.tile = 16;
  farm::ShotSpec shot = shotSpec(spec);
  shot.add_required_tags("big");
  const int64_t id = client().submit(shot);
  ASSERT_EQ(waitForShot(id, 60s).state(), farm::SHOT_DONE);
  const FarmDatabase db = database();
  EXPECT_EQ(db.integer("SELECT COUNT(*) FROM attempts a JOIN workers w ON w.id = a.worker_id WHERE w.name = 'plain'"), 0);
  EXPECT_EQ(db.integer("SELECT COUNT(*) FROM attempts a JOIN workers w ON w.id = a.worker_id WHERE w.name = 'tagged'"),
            spec.tasks());
  // A tag the scheduler cannot store is refused at submission.
  farm::ShotSpec bad = shotSpec(spec);
  bad.add_required_tags("no,commas");
  EXPECT_THROW(client().submit(bad), farm::FarmError);

  // A worker offering such a tag is refused too, and says so and stops rather than retrying.
  const std::optional<int> exited = startWorker("badly-tagged", {"--tags", "a b"}).wait(20s);
  ASSERT_TRUE(exited.has_value()) << "the refused worker kept retrying";
  EXPECT_NE(*exited, 0);
  EXPECT_TRUE(contains(workerLog("badly-tagged"), "refused this worker")) << workerLog("badly-tagged");
}

}  // namespace
}  // namespace pathfarm::farmtest
