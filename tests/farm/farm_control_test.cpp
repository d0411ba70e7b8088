// Controls of a shot from the CLI on a real farm: a frame requeued after the shot is done
// renders again, the shot ends again with the same bytes, and what cannot be requeued is
// refused with a message and exit status 2; a shot submitted --after another starts when
// that one is done.
#include "farm/farm_fixture.h"

namespace pathfarm::farmtest {
namespace {

TEST_F(FarmTest, ARequeuedFrameRendersAgainToTheSameBytes) {
  RenderSpec spec;
  spec.name = "requeue";
  spec.frameEnd = 2;
  const std::string scheduler = startScheduler();
  startWorker("w1");
  const CommandResult submitted = runPathfarm({"submit", writeShotFile(spec).string(), "--scheduler", scheduler});
  ASSERT_EQ(submitted.status, 0) << submitted.output;
  const int64_t id = shotIdFrom(submitted);
  ASSERT_EQ(waitForShot(id, 60s).state(), farm::SHOT_DONE);
  ASSERT_EQ(database().integer("SELECT COUNT(*) FROM attempts"), spec.tasks());

  const CommandResult requeued =
      runPathfarm({"requeue", std::to_string(id), "--frame", "1", "--scheduler", scheduler});
  ASSERT_EQ(requeued.status, 0) << requeued.output;
  ASSERT_EQ(waitForShot(id, 60s).state(), farm::SHOT_DONE);
  // Frame 1's tiles and assembly ran once more, all done (state 1); the other frames did not.
  EXPECT_EQ(database().integer("SELECT COUNT(*) FROM attempts"), spec.tasks() + spec.tilesPerFrame() + 1);
  EXPECT_EQ(database().integer("SELECT COUNT(*) FROM attempts WHERE state != 1"), 0);
  expectSameFrames(fetchFrames(id, "fetched"), renderLocally(spec), spec);

  const auto refused = [&](const std::vector<std::string>& arguments, const std::string& message) {
    std::vector<std::string> command = {"requeue", std::to_string(id), "--scheduler", scheduler};
    command.insert(command.end(), arguments.begin(), arguments.end());
    const CommandResult result = runPathfarm(command);
    EXPECT_NE(result.status, 0) << result.output;
    EXPECT_TRUE(contains(result.output, message)) << result.output;
    return result.status;
  };
  EXPECT_EQ(refused({"--task", "99999"}, "has no task 99999"), 2);
  EXPECT_EQ(refused({"--frame", "7"}, "no task for frame 7"), 2);
  refused({}, "give --task ID or --frame N");
}

TEST_F(FarmTest, AShotSubmittedAfterAnotherStartsWhenThatOneIsDone) {
  RenderSpec first;
  first.name = "first";
  RenderSpec second = first;
  second.name = "second";
  const std::string scheduler = startScheduler();
  const CommandResult a = runPathfarm({"submit", writeShotFile(first).string(), "--scheduler", scheduler});
  ASSERT_EQ(a.status, 0) << a.output;
  const int64_t firstId = shotIdFrom(a);
  const CommandResult b = runPathfarm(
      {"submit", writeShotFile(second).string(), "--scheduler", scheduler, "--after", std::to_string(firstId)});
  ASSERT_EQ(b.status, 0) << b.output;
  const int64_t secondId = shotIdFrom(b);
  // Above the first in priority, it would be leased first if it did not wait.
  ASSERT_EQ(runPathfarm({"priority", std::to_string(secondId), "5", "--scheduler", scheduler}).status, 0);
  startWorker("w1");
  ASSERT_EQ(waitForShot(secondId, 60s).state(), farm::SHOT_DONE);
  // The second shot's first lease came after the first shot had ended.
  EXPECT_EQ(database().integer("SELECT (SELECT MIN(a.leased_at) FROM attempts a JOIN tasks t ON t.id = a.task_id "
                               "WHERE t.shot_id = " + std::to_string(secondId) +
                               ") >= (SELECT finished_at FROM shots WHERE id = " + std::to_string(firstId) + ")"),
            1);

  const CommandResult refused =
      runPathfarm({"submit", writeShotFile(second).string(), "--scheduler", scheduler, "--after", "999"});
  EXPECT_EQ(refused.status, 2) << refused.output;
  EXPECT_TRUE(contains(refused.output, "shot 999 does not exist")) << refused.output;
}

}  // namespace
}  // namespace pathfarm::farmtest
