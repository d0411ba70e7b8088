// Inputs without shared storage: `pathfarm submit` uploads the scene with its textures and
// meshes, the author's copy disappears before any worker starts, and the workers render
// the same bytes from the uploaded files. A second submit sends nothing, and a spec whose
// files leave the scene's folder or were never uploaded is refused.
#include "farm/farm_fixture.h"
#include "proto/wire/sha256.h"

namespace pathfarm::farmtest {
namespace {

TEST_F(FarmTest, AnUploadedSceneRendersAfterTheAuthorsCopyIsGone) {
  // The materials scene: a PNG texture, an OBJ and a PLY mesh beside its JSON.
  const fs::path author = dir() / "author";
  fs::create_directories(author);
  fs::copy(fs::path(PATHFARM_SOURCE_DIR) / "scenes" / "materials", author / "materials");
  RenderSpec spec;
  spec.name = "uploaded";
  spec.scene = author / "materials" / "scene.json";
  spec.frameEnd = 1;
  const fs::path local = renderLocally(spec);

  const std::string scheduler = startScheduler();
  const CommandResult submitted = runPathfarm({"submit", writeShotFile(spec).string(), "--scheduler", scheduler});
  ASSERT_EQ(submitted.status, 0) << submitted.output;
  EXPECT_TRUE(contains(submitted.output, "scene: 4 files")) << submitted.output;
  EXPECT_TRUE(contains(submitted.output, "sent 4")) << submitted.output;
  const int64_t id = shotIdFrom(submitted);
  fs::rename(author, dir() / "author-gone");

  startWorker("w1");
  ASSERT_EQ(waitForShot(id, 60s).state(), farm::SHOT_DONE);
  expectSameFrames(fetchFrames(id, "fetched"), local, spec);
  const farm::ShotSpec stored = client().shot(id).spec();
  EXPECT_EQ(stored.scene(), "scene.json");
  EXPECT_EQ(stored.inputs_size(), 4);
  EXPECT_TRUE(fs::exists(dir() / "cache" / "w1" / "scenes")) << "the worker rebuilt the scene in its cache";

  // The same scene again: the farm has every file, nothing is sent.
  fs::rename(dir() / "author-gone", author);
  const CommandResult again = runPathfarm({"submit", writeShotFile(spec).string(), "--scheduler", scheduler});
  ASSERT_EQ(again.status, 0) << again.output;
  EXPECT_TRUE(contains(again.output, "sent 0")) << again.output;
}

TEST_F(FarmTest, SceneFilesLeavingTheirFolderOrNeverUploadedAreRefused) {
  startScheduler();
  RenderSpec spec;
  farm::ShotSpec shot = shotSpec(spec);
  const std::string bytes = readFile(cornellScene());
  farm::ChunkRef ref;
  ref.set_sha256(farm::sha256Hex(bytes));
  ref.set_size(static_cast<int64_t>(bytes.size()));
  farm::InputFile* file = shot.add_inputs();
  file->set_path("scene.json");
  *file->mutable_chunk() = ref;
  shot.set_scene("scene.json");

  const auto refusal = [&](const farm::ShotSpec& s) {
    try {
      client().submit(s);
    } catch (const farm::FarmError& e) {
      EXPECT_EQ(e.code(), grpc::StatusCode::INVALID_ARGUMENT) << e.what();
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_TRUE(contains(refusal(shot), "was not uploaded")) << refusal(shot);
  client().putInput(bytes, ref);
  EXPECT_TRUE(client().missingInputs({ref}).empty());
  for (const char* path : {"../../etc/passwd", "/etc/passwd", "a/../../b", "a//b", "a\\..\\b"}) {
    farm::ShotSpec hostile = shot;
    hostile.mutable_inputs(0)->set_path(path);
    hostile.set_scene(path);
    EXPECT_TRUE(contains(refusal(hostile), "not a relative path inside")) << path;
  }
  farm::ShotSpec elsewhere = shot;
  elsewhere.set_scene("other.json");
  EXPECT_TRUE(contains(refusal(elsewhere), "not among the shot's uploaded files"));
  EXPECT_EQ(database().integer("SELECT COUNT(*) FROM shots"), 0);
  EXPECT_EQ(refusal(shot), "accepted") << "the file is in the store now";
}

}  // namespace
}  // namespace pathfarm::farmtest
