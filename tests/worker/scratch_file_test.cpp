// A worker's scratch files go when their holder lets go, and those a killed worker left
// behind go when a worker starts, unless their process still runs.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>

#include "test_support.h"
#include "worker/scratch_file.h"

namespace pathfarm::farm {
namespace {

TEST(ScratchFile, TheFileGoesWithItsLastHolder) {
  const auto folder = test_support::processTemporaryFolder("pathfarm_scratch") / "held";
  const std::filesystem::path path = scratchPathFor(folder, "frame.exr");
  EXPECT_EQ(path.filename().string(), std::to_string(getpid()) + "-frame.exr");
  {
    const ScratchFile file(path);
    std::ofstream(file.path()) << "pixels";
    EXPECT_TRUE(std::filesystem::exists(path));
  }
  EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(ScratchFile, OnlyFilesOfProcessesThatNoLongerRunAreOrphans) {
  const pid_t child = fork();
  if (child == 0) _exit(0);
  ASSERT_GT(child, 0);
  ASSERT_EQ(waitpid(child, nullptr, 0), child);  // reaped: its pid names no process now
  const auto folder = test_support::processTemporaryFolder("pathfarm_scratch") / "orphans";
  std::filesystem::create_directories(folder);
  const std::string dead = std::to_string(child) + "-frame.exr", alive = std::to_string(getpid()) + "-frame.exr";
  for (const std::string& name : {dead, alive, std::string("notes-1.txt"), std::string("-1.exr")})
    std::ofstream(folder / name) << "bytes";
  removeOrphanedScratchFiles(folder);
  EXPECT_FALSE(std::filesystem::exists(folder / dead));
  EXPECT_TRUE(std::filesystem::exists(folder / alive));
  EXPECT_TRUE(std::filesystem::exists(folder / "notes-1.txt"));
  EXPECT_TRUE(std::filesystem::exists(folder / "-1.exr"));
  removeOrphanedScratchFiles(folder / "absent");  // no folder yet: nothing to do
}

}  // namespace
}  // namespace pathfarm::farm
