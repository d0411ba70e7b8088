// Retention on a running farm: `pathfarm scheduler --retain-days D` deletes a shot D days
// after it finished, with its records and the chunk files only it named, while a shot
// submitted after it runs on undisturbed.
#include "farm/farm_fixture.h"

namespace pathfarm::farmtest {
namespace {

// Chunk files under the store.
size_t chunkFiles(const fs::path& store) {
  size_t count = 0;
  for (const auto& entry : fs::recursive_directory_iterator(store)) count += entry.is_regular_file() ? 1 : 0;
  return count;
}

TEST_F(FarmTest, AShotPastItsRetentionGoesWithItsChunks) {
  SchedulerConfig config;
  config.extraArguments = {"--retain-days", "0.00003"};  // 2.6 s
  startScheduler(config);
  startWorker("w1");
  const FarmDatabase db = database();

  RenderSpec spec;
  spec.name = "short-lived";
  spec.width = 32;
  spec.height = 32;
  spec.tile = 16;
  const int64_t id = client().submit(shotSpec(spec));
  ASSERT_EQ(waitForShot(id, 30s).state(), farm::SHOT_DONE);
  const size_t files = chunkFiles(storeFolder());
  EXPECT_GE(files, 1u) << "the frame (its four tiles leave the store once it is assembled)";

  // The rows go first, then the files.
  ASSERT_TRUE(waitUntil([&] { return db.integer("SELECT COUNT(*) FROM shots") == 0 && chunkFiles(storeFolder()) == 0; },
                        20s))
      << "the shot or its chunk files outlived its retention";
  for (const char* table : {"tasks", "attempts", "task_deps", "events WHERE shot_id IS NOT NULL", "chunks"})
    EXPECT_EQ(db.integer(std::string("SELECT COUNT(*) FROM ") + table), 0) << table;
  try {
    client().shot(id);
    ADD_FAILURE() << "the deleted shot is still served";
  } catch (const farm::FarmError& e) {
    EXPECT_EQ(e.code(), grpc::StatusCode::NOT_FOUND) << e.what();
  }

  // The farm goes on: a new shot renders and is kept until its own time.
  spec.name = "next";
  const int64_t next = client().submit(shotSpec(spec));
  EXPECT_EQ(waitForShot(next, 30s).state(), farm::SHOT_DONE);
}

}  // namespace
}  // namespace pathfarm::farmtest
