// The reference cache as a user meets it: `pathfarm submit --reference-cache` and
// `pathfarm fetch --reference-cache` keep a shot's references, the next shot of the same
// scene and settings renders none and measures the same errors, and a texture that
// changed, however slightly, renders the reference anew.
#include <fstream>

#include "farm/farm_fixture.h"
#include "scheduler/shot_report.h"

namespace pathfarm::farmtest {
namespace {

// The shot's render tiles of its references, by frame, read from the farm's database.
std::map<int64_t, int> referenceTiles(const FarmDatabase& db, int64_t shotId) {
  std::map<int64_t, int> tiles;
  for (const auto& row : db.rows("SELECT hex(params) FROM tasks WHERE shot_id = " + std::to_string(shotId) +
                                 " AND kind = " + std::to_string(int{farm::TASK_RENDER_TILE}))) {
    std::string bytes;
    for (size_t i = 0; i + 1 < row[0].size(); i += 2)
      bytes.push_back(static_cast<char>(std::stoi(row[0].substr(i, 2), nullptr, 16)));
    farm::TaskParams params;
    EXPECT_TRUE(params.ParseFromString(bytes));
    if (params.role() == farm::ROLE_REFERENCE) ++tiles[params.frame()];
  }
  return tiles;
}

size_t filesIn(const fs::path& folder) {
  if (!fs::exists(folder)) return 0;
  return static_cast<size_t>(std::distance(fs::directory_iterator(folder), fs::directory_iterator()));
}

TEST_F(FarmTest, ASecondShotTakesItsReferenceFromTheCacheUntilATextureChanges) {
  const fs::path author = dir() / "author";
  fs::create_directories(author);
  fs::copy(fs::path(PATHFARM_SOURCE_DIR) / "scenes" / "materials", author / "materials");
  const fs::path shot = dir() / "cached.shot.json";
  writeFile(shot, R"({"name": "cached", "scene": ")" + (author / "materials" / "scene.json").string() + R"(",
    "frames": {"start": 0, "end": 1}, "resolution": [48, 32], "spp": 2, "max_depth": 3, "tile": 32,
    "pipeline": "pt", "reference_spp": 32, "evaluation_frames": [1]})");
  const fs::path cache = dir() / "references";
  const std::string scheduler = startScheduler();
  startWorker("w1");
  const FarmDatabase db(databaseFile());
  const auto run = [&](const std::string& name) {
    const CommandResult submitted =
        runPathfarm({"submit", shot.string(), "--scheduler", scheduler, "--reference-cache", cache.string()});
    EXPECT_EQ(submitted.status, 0) << submitted.output;
    const int64_t id = shotIdFrom(submitted);
    EXPECT_EQ(waitForShot(id, 60s).state(), farm::SHOT_DONE);
    fetchFrames(id, name, {"--reference-cache", cache.string()});
    return std::pair{id, client().report(id)};
  };

  const auto [first, firstReport] = run("first");
  EXPECT_EQ(referenceTiles(db, first), (std::map<int64_t, int>{{1, 2}}));
  EXPECT_EQ(firstReport.cached_references(), 0);
  EXPECT_EQ(filesIn(cache), 1u) << "fetch kept the reference";

  const auto [second, secondReport] = run("second");
  EXPECT_TRUE(referenceTiles(db, second).empty()) << "the cached reference is not rendered again";
  EXPECT_EQ(secondReport.cached_references(), 1);
  ASSERT_EQ(secondReport.errors_size(), firstReport.errors_size());
  ASSERT_GT(firstReport.errors_size(), 0);
  EXPECT_EQ(secondReport.errors(0).relmse(), firstReport.errors(0).relmse()) << "the same reference's bits";
  EXPECT_TRUE(contains(farm::reportMarkdown(secondReport), "came from the reference cache"));

  // Bytes after the PNG's end change no pixel, yet the texture file is another one.
  std::ofstream(author / "materials" / "checker.png", std::ios::app) << "edited";
  const auto [third, thirdReport] = run("third");
  EXPECT_EQ(referenceTiles(db, third), (std::map<int64_t, int>{{1, 2}}));
  EXPECT_EQ(thirdReport.cached_references(), 0);
  EXPECT_EQ(filesIn(cache), 2u);
}

}  // namespace
}  // namespace pathfarm::farmtest
