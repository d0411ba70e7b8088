// The command for a shot's outcome runs with the shot in its environment, the other does
// not, and one that outlasts its limit is stopped.
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <iterator>

#include "client/shot_hooks.h"
#include "test_support.h"

namespace pathfarm::farm {
namespace {

std::filesystem::path hookFile(const std::string& name) {
  const auto folder = test_support::processTemporaryFolder("pathfarm_shot_hooks");
  std::filesystem::create_directories(folder);
  return folder / name;
}

std::string contents(const std::filesystem::path& file) {
  std::ifstream in(file);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(ShotHooks, TheOutcomesCommandRunsWithTheShotInItsEnvironment) {
  const auto done = hookFile("done.txt"), failed = hookFile("failed.txt");
  const ShotHooks hooks{
      "echo \"$PATHFARM_SHOT_ID $PATHFARM_SHOT_NAME $PATHFARM_SHOT_STATE $PATHFARM_SHOT_OUTPUT\" > " + done.string(),
      "echo failed > " + failed.string() + "; exit 3"};
  EXPECT_EQ(runShotHook(hooks, {7, "dolly", true, "SHOT_DONE", "/frames/dolly"}), 0);
  EXPECT_EQ(contents(done), "7 dolly SHOT_DONE /frames/dolly\n");
  EXPECT_FALSE(std::filesystem::exists(failed));
  EXPECT_EQ(runShotHook(hooks, {8, "dolly", false, "SHOT_CANCELLED", ""}), 3);
  EXPECT_EQ(contents(failed), "failed\n");
  EXPECT_EQ(runShotHook({}, {9, "dolly", true, "SHOT_DONE", ""}), std::nullopt);
}

TEST(ShotHooks, ACommandThatOutlastsItsLimitIsStopped) {
  const auto start = std::chrono::steady_clock::now();
  const auto status = runShotHook({"exec sleep 30", ""}, {1, "s", true, "SHOT_DONE", ""}, std::chrono::milliseconds(200));
  ASSERT_TRUE(status.has_value());
  EXPECT_NE(*status, 0);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(15));
}

}  // namespace
}  // namespace pathfarm::farm
