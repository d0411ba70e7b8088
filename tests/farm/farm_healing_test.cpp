// A farm heals a chunk its store lost: fetching a frame whose chunk is damaged on disk, or
// a task that needs a tile whose file is gone (released once its frame was assembled, or
// lost), runs the task that made it again (and what used it), and the shot ends with the
// same bytes as an undisturbed render.
#include "farm/farm_fixture.h"

namespace pathfarm::farmtest {
namespace {

TEST_F(FarmTest, ALostOrDamagedChunkIsMadeAgainByTheTaskThatMadeIt) {
  RenderSpec spec;
  spec.name = "healing";
  spec.frameEnd = 1;
  const std::string scheduler = startScheduler();
  startWorker("w1");
  const int64_t id = client().submit(shotSpec(spec));
  ASSERT_EQ(waitForShot(id, 60s).state(), farm::SHOT_DONE);
  stopWorkers();  // the next worker's cache holds nothing: it must fetch from the store
  const FarmDatabase db = database();
  const auto outputOf = [&](const std::string& where) {
    const auto rows = db.rows("SELECT output_sha FROM tasks WHERE " + where + " ORDER BY id LIMIT 1");
    return rows.at(0).at(0);
  };
  // Frame 0's EXR is damaged on disk; the tiles left the store once their frames were
  // assembled (the scheduler removes them within a second), their rows stayed.
  const std::string frameSha = outputOf("kind = 2");
  const std::string tileSha = outputOf("kind = 1 AND id > (SELECT MIN(id) FROM tasks WHERE kind = 2)");
  writeFile(chunkFile(frameSha), "damaged");
  for (int waited = 0; fs::exists(chunkFile(tileSha)) && waited < 50; ++waited) std::this_thread::sleep_for(100ms);
  EXPECT_FALSE(fs::exists(chunkFile(tileSha))) << "a tile outlived its frame's assembly";
  for (const auto& row : db.rows("SELECT output_sha FROM tasks WHERE kind = 1"))
    EXPECT_FALSE(fs::exists(chunkFile(row.at(0)))) << "tile " << row.at(0);
  EXPECT_EQ(db.integer("SELECT COUNT(*) FROM chunks WHERE sha256 = '" + tileSha + "'"), 1);

  const CommandResult fetched =
      runPathfarm({"fetch", std::to_string(id), "--out", (dir() / "first-try").string(), "--scheduler", scheduler});
  EXPECT_NE(fetched.status, 0) << fetched.output;
  EXPECT_TRUE(contains(fetched.output, "run again")) << fetched.output;
  EXPECT_EQ(client().shot(id).summary().state(), farm::SHOT_RUNNING);

  // The frame-1 assembly needs the lost tile: asking for it re-renders it first.
  const std::string assembly = db.rows("SELECT id FROM tasks WHERE kind = 2 ORDER BY id DESC LIMIT 1").at(0).at(0);
  ASSERT_EQ(runPathfarm({"requeue", std::to_string(id), "--task", assembly, "--scheduler", scheduler}).status, 0);
  startWorker("w2");
  ASSERT_EQ(waitForShot(id, 60s).state(), farm::SHOT_DONE);
  EXPECT_EQ(db.integer("SELECT COUNT(*) FROM attempts a JOIN tasks t ON t.id = a.task_id WHERE t.output_sha = '" +
                       tileSha + "' AND a.state = 1"),
            2)
      << "the tile was rendered again, to the same bytes";
  expectSameFrames(fetchFrames(id, "fetched"), renderLocally(spec), spec);
  const auto shot = client().shot(id);  // kept: the loop must not range over a temporary's field
  std::string events;
  for (const auto& event : shot.events()) events += event.message() + "\n";
  EXPECT_TRUE(contains(events, "was missing or damaged")) << events;
  EXPECT_EQ(db.integer("SELECT COUNT(*) FROM worker_failures"), 0) << "no worker was blamed for the store's loss";
  // The stopped worker's last long-poll, cancelled as it stopped, was handed no task (one
  // would have waited a whole lease period to expire).
  EXPECT_EQ(db.integer("SELECT COUNT(*) FROM attempts WHERE state = 3"), 0);
}

}  // namespace
}  // namespace pathfarm::farmtest
