// A worker's side of uploaded scenes: the files are rebuilt once in a folder named by
// their digests, an unsafe list is refused before anything is written, and the cache is
// trimmed to its bound oldest first, sparing what was used recently.
#include "worker/scene_files.h"

#include <gtest/gtest.h>

#include <fstream>
#include <map>

#include "proto/wire/input_files.h"
#include "proto/wire/sha256.h"
#include "worker/cache_trim.h"
#include "worker/failure_class.h"
#include "test_support.h"

namespace pathfarm::farm {
namespace {

namespace fs = std::filesystem;

class SceneFilesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() /
            ("pathfarm_scene_files_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(root_);
  }
  void TearDown() override { fs::remove_all(root_); }

  void add(ShotSpec& spec, const std::string& path, const std::string& bytes) {
    InputFile* file = spec.add_inputs();
    file->set_path(path);
    file->mutable_chunk()->set_sha256(sha256Hex(bytes));
    file->mutable_chunk()->set_size(static_cast<int64_t>(bytes.size()));
    store_[file->chunk().sha256()] = bytes;
  }
  TaskRunner::ChunkFetcher fetcher() {
    return [this](const ChunkRef& ref) {
      ++fetches_;
      return store_.at(ref.sha256());
    };
  }
  static std::string read(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
  }

  fs::path root_;
  std::map<std::string, std::string> store_;
  int fetches_ = 0;
};

TEST_F(SceneFilesTest, UploadedFilesAreRebuiltOnceWhereTheSceneExpectsThem) {
  ShotSpec spec;
  spec.set_scene("shots/scene.json");
  add(spec, "shots/scene.json", "{\"shapes\": []}");
  add(spec, "textures/wood.png", "png bytes");
  const fs::path scene = localSceneFile(spec, root_, fetcher());
  EXPECT_EQ(scene, root_ / inputFilesDigest(spec) / "shots" / "scene.json");
  EXPECT_EQ(read(scene), "{\"shapes\": []}");
  EXPECT_EQ(read(scene.parent_path().parent_path() / "textures" / "wood.png"), "png bytes");
  EXPECT_EQ(fetches_, 2);
  EXPECT_EQ(localSceneFile(spec, root_, fetcher()), scene);
  EXPECT_EQ(fetches_, 2) << "the second task of the shot finds the folder complete";
}

TEST_F(SceneFilesTest, ASharedPathIsUsedAsItIs) {
  const fs::path shared = fs::path(PATHFARM_SOURCE_DIR) / "scenes" / "cornell" / "scene.json";
  ShotSpec spec;
  spec.set_scene(shared.string());
  EXPECT_EQ(localSceneFile(spec, root_, fetcher()), shared);
  EXPECT_FALSE(fs::exists(root_));
}

TEST_F(SceneFilesTest, ASharedPathThisWorkerCannotSeeIsTheWorkersFaultNotTheScenes) {
  ShotSpec spec;
  spec.set_scene("/studio/shots/scene.json");  // storage not mounted here
  try {
    localSceneFile(spec, root_, fetcher());
    ADD_FAILURE() << "a missing shared scene was handed to the renderer";
  } catch (const std::exception& e) {
    EXPECT_EQ(classifyFailure(e), FAILURE_WORKER_FAULT) << e.what();
    EXPECT_NE(std::string(e.what()).find("/studio/shots/scene.json"), std::string::npos) << e.what();
  }
}

TEST_F(SceneFilesTest, AFileLeavingTheFolderIsRefusedBeforeAnythingIsWritten) {
  ShotSpec spec;
  spec.set_scene("scene.json");
  add(spec, "scene.json", "{}");
  add(spec, "../../outside.txt", "hostile");
  EXPECT_THROW(localSceneFile(spec, root_, fetcher()), std::invalid_argument);
  EXPECT_EQ(fetches_, 0);
  EXPECT_FALSE(fs::exists(root_.parent_path() / "outside.txt"));
}

TEST(CacheTrim, OldestEntriesGoFirstAndRecentOnesStay) {
  const fs::path cache = test_support::processTemporaryFolder("pathfarm_cache_trim");
  fs::remove_all(cache);
  const auto write = [](const fs::path& file, size_t bytes, std::chrono::hours age) {
    fs::create_directories(file.parent_path());
    std::ofstream(file) << std::string(bytes, 'x');
    fs::last_write_time(file, fs::file_time_type::clock::now() - age);
  };
  write(cache / "objects" / "aa" / "old", 400, std::chrono::hours(30));
  write(cache / "objects" / "bb" / "newer", 400, std::chrono::hours(20));
  write(cache / "scenes" / "s1" / "scene.json", 300, std::chrono::hours(25));
  fs::last_write_time(cache / "scenes" / "s1", fs::file_time_type::clock::now() - std::chrono::hours(25));
  write(cache / "objects" / "cc" / "recent", 400, std::chrono::hours(0));

  const TrimResult trimmed = trimCache(cache, 900, std::chrono::seconds(600));
  EXPECT_EQ(trimmed.bytesBefore, 1500u);
  EXPECT_EQ(trimmed.bytesRemoved, 700u);  // the oldest chunk, then the scene folder
  EXPECT_FALSE(fs::exists(cache / "objects" / "aa" / "old"));
  EXPECT_FALSE(fs::exists(cache / "scenes" / "s1"));
  EXPECT_TRUE(fs::exists(cache / "objects" / "bb" / "newer"));
  EXPECT_TRUE(fs::exists(cache / "objects" / "cc" / "recent"));

  // Under the bound only what is recent is left; nothing recent goes, even over the bound.
  EXPECT_EQ(trimCache(cache, 100, std::chrono::seconds(600)).bytesRemoved, 400u);
  EXPECT_TRUE(fs::exists(cache / "objects" / "cc" / "recent"));
  fs::remove_all(cache);
}

}  // namespace
}  // namespace pathfarm::farm
