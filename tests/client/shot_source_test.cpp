// A scene file given where a shot file is expected becomes a shot of its own, and shot
// keys from the command line are set over a file's, checked as the file's own keys are.
#include <gtest/gtest.h>

#include <fstream>

#include "client/shot_preparation.h"
#include "client/shot_source.h"
#include "renderer/scene/json_node.h"
#include "test_support.h"

namespace pathfarm::farm {
namespace {

std::filesystem::path cornellScene() { return test_support::sourceDir() / "scenes/cornell/scene.json"; }

std::filesystem::path writeFile(const std::string& name, const std::string& text) {
  const auto folder = test_support::processTemporaryFolder("pathfarm_shot_sources");
  std::filesystem::create_directories(folder);
  std::ofstream(folder / name) << text;
  return folder / name;
}

TEST(ShotSource, AJsonSceneIsRenderedAsAShotNamedAfterItWithItsOwnSettings) {
  ASSERT_TRUE(isSceneFile(cornellScene()));
  const ShotFile file = loadShotSource(cornellScene(), nlohmann::json::object());
  ASSERT_NE(file.scene(), nullptr);
  const ShotSpec& spec = file.spec();
  EXPECT_EQ(spec.name(), "scene");
  EXPECT_EQ(std::filesystem::path(spec.scene()), cornellScene());
  EXPECT_EQ(spec.frame_start(), file.scene()->defaults.frameStart);
  EXPECT_EQ(spec.frame_end(), file.scene()->defaults.frameEnd);
  EXPECT_EQ(spec.width(), file.scene()->defaults.width);
  EXPECT_EQ(spec.spp(), file.scene()->defaults.spp);
  EXPECT_EQ(std::filesystem::path(spec.output()), cornellScene().parent_path() / "output/scene");
}

TEST(ShotSource, KeysFromTheCommandLineAreSetOverTheSceneAndTheShotFile) {
  const nlohmann::json keys = {{"frames", {{"start", 2}, {"end", 3}}}, {"spp", 5}, {"pipeline", "pt"}};
  const ShotSpec fromScene = loadShotSource(cornellScene(), keys).spec();
  EXPECT_EQ(fromScene.frame_start(), 2);
  EXPECT_EQ(fromScene.frame_end(), 3);
  EXPECT_EQ(fromScene.spp(), 5);
  EXPECT_EQ(fromScene.pipeline(), PIPELINE_PT);

  const auto shot = writeFile("shot.json", R"({"scene": ")" + cornellScene().string() +
                                               R"(", "spp": 9, "tile": 16, "pipeline": "d"})");
  EXPECT_FALSE(isSceneFile(shot));
  const ShotSpec fromShot = loadShotSource(shot, keys).spec();
  EXPECT_EQ(fromShot.spp(), 5);          // the command line's
  EXPECT_EQ(fromShot.tile(), 16);        // the file's
  EXPECT_EQ(fromShot.pipeline(), PIPELINE_PT);
  EXPECT_EQ(fromShot.name(), "shot");
}

TEST(ShotSource, ABadKeyFromTheCommandLineIsRefusedByName) {
  const auto refusal = [](const nlohmann::json& keys) {
    try {
      loadShotSource(cornellScene(), keys);
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(refusal({}), "(no error)");
  EXPECT_NE(refusal({{"sp", 4}}).find("sp: unknown key"), std::string::npos);
  EXPECT_NE(refusal({{"spp", 0}}).find("spp"), std::string::npos);
  // A file that is neither a scene nor a shot reads as a shot, whose message names its key.
  const auto neither = writeFile("neither.json", R"({"colour": "blue"})");
  EXPECT_FALSE(isSceneFile(neither));
  try {
    loadShotSource(neither, {});
    ADD_FAILURE() << "a file with no scene was accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("colour"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pathfarm::farm
