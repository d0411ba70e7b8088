// A submit repeated with its key (a script retrying `pathfarm submit` after a timeout)
// prints the same shot and queues nothing more; without a key each submit is a shot.
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
}

}  // namespace
}  // namespace pathfarm::farmtest
