#include <gtest/gtest.h>

#include <fstream>

#include "renderer/scene/json_node.h"
#include "scheduler/shot_file.h"
#include "test_support.h"

namespace pathfarm::farm {
namespace {

// Shot files in a temporary folder that links to the demo scene's folder, so relative
// scene paths are resolved against the shot file's own folder as in real use.
std::filesystem::path writeShot(const std::string& name, const std::string& json) {
  const auto folder = std::filesystem::temp_directory_path() / "pathfarm_shot_files";
  std::filesystem::create_directories(folder);
  std::error_code exists;
  std::filesystem::create_directory_symlink(test_support::sourceDir() / "scenes/cornell", folder / "cornell", exists);
  const auto file = folder / ("test_" + name + ".json");
  std::ofstream(file) << json;
  return file;
}

std::string errorOf(const std::string& json) {
  const auto file = writeShot("bad", json);
  std::string message = "(no error)";
  try {
    loadShotFile(file);
  } catch (const SceneError& e) {
    message = e.what();
  }
  std::filesystem::remove(file);
  return message;
}

TEST(ShotFile, FillsDefaultsFromTheSceneAndMakesPathsAbsolute) {
  const auto file = writeShot("defaults", R"({"scene": "cornell/scene.json", "frames": {"start": 3, "end": 5}, "tile": 16})");
  const ShotSpec spec = loadShotFile(file);
  std::filesystem::remove(file);
  EXPECT_EQ(spec.name(), "test_defaults");
  EXPECT_EQ(spec.pipeline(), "pt");
  EXPECT_EQ(spec.scene(), (file.parent_path() / "cornell/scene.json").string());
  EXPECT_EQ(spec.frame_start(), 3);
  EXPECT_EQ(spec.frame_end(), 5);
  EXPECT_EQ(spec.width(), 256);  // the scene's render defaults
  EXPECT_EQ(spec.spp(), 64);
  EXPECT_EQ(spec.max_depth(), 8);
  EXPECT_EQ(spec.tile(), 16);
  EXPECT_EQ(spec.max_attempts(), 3);
  EXPECT_TRUE(std::filesystem::path(spec.output()).is_absolute());
}

TEST(ShotFile, BadShotsAreRefusedWithFileAndKey) {
  EXPECT_NE(errorOf(R"({"scene": "cornell/scene.json", "pipeline": "dui2"})").find("pipeline: unknown pipeline \"dui2\""),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"scene": "cornell/nowhere.json"})").find("nowhere.json: cannot open the scene file"),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"scene": "cornell/scene.json", "tiles": 5})").find("tiles: unknown key"), std::string::npos);
  EXPECT_NE(errorOf(R"({"scene": "cornell/scene.json", "frames": {"start": 4, "end": 1}})").find("frames.end"),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"scene": "cornell/scene.json", "tile": 2})").find("tile: 2 is out of range"), std::string::npos);
  EXPECT_NE(errorOf(R"({"scene": )").find("invalid JSON"), std::string::npos);
  EXPECT_NE(errorOf(R"({"scene": "cornell/scene.json", "decompose": "x=E(D"})").find("decompose: light-path expression"),
            std::string::npos);
}

TEST(ShotFile, ResolvesTheDecompositionOnceForEveryWorker) {
  const auto file = writeShot("split", R"({"scene": "cornell/scene.json", "decompose": "default"})");
  EXPECT_EQ(loadShotFile(file).decompose(),
            "diffuse_direct=ED,diffuse_indirect=ED.+,reflection=ERD.*,transmission=ETTD.*,residual");
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace pathfarm::farm
