// The rules every party applies to a shot's uploaded scene files.
#include "proto/wire/input_files.h"

#include <gtest/gtest.h>

#include "proto/wire/sha256.h"

namespace pathfarm::farm {
namespace {

ShotSpec withFiles(const std::vector<std::string>& paths, const std::string& scene) {
  ShotSpec spec;
  spec.set_scene(scene);
  for (const std::string& path : paths) {
    InputFile* file = spec.add_inputs();
    file->set_path(path);
    file->mutable_chunk()->set_sha256(sha256Hex(path));
    file->mutable_chunk()->set_size(static_cast<int64_t>(path.size()));
  }
  return spec;
}

TEST(InputFiles, OnlyRelativePathsInsideTheFolderAreSafe) {
  for (const char* good : {"scene.json", "textures/wood.png", "a/b/c.obj", "..hidden", "dots.../x"})
    EXPECT_TRUE(isSafeInputPath(good)) << good;
  for (const char* bad : {"", "/etc/passwd", "../x", "a/../../x", "a/..", "./x", "a/./x", "a//b", "a/", "a\\..\\b"})
    EXPECT_FALSE(isSafeInputPath(bad)) << bad;
  EXPECT_FALSE(isSafeInputPath(std::string("a\0b", 3)));
  EXPECT_FALSE(isSafeInputPath(std::string(2000, 'a')));
}

TEST(InputFiles, AListMustNameTheSceneOnceEachWithAValidChunk) {
  EXPECT_NO_THROW(checkInputFiles(ShotSpec()));  // shared storage: nothing to check
  EXPECT_NO_THROW(checkInputFiles(withFiles({"scene.json", "tex/a.png"}, "scene.json")));
  EXPECT_THROW(checkInputFiles(withFiles({"tex/a.png"}, "scene.json")), std::invalid_argument);
  EXPECT_THROW(checkInputFiles(withFiles({"scene.json", "scene.json"}, "scene.json")), std::invalid_argument);
  EXPECT_THROW(checkInputFiles(withFiles({"scene.json", "../a.png"}, "scene.json")), std::invalid_argument);
  ShotSpec badChunk = withFiles({"scene.json"}, "scene.json");
  badChunk.mutable_inputs(0)->mutable_chunk()->set_sha256("not hex");
  EXPECT_THROW(checkInputFiles(badChunk), std::invalid_argument);
}

TEST(InputFiles, TheDigestNamesTheFilesNotTheirOrder) {
  const std::string digest = inputFilesDigest(withFiles({"scene.json", "a.png"}, "scene.json"));
  EXPECT_EQ(inputFilesDigest(withFiles({"a.png", "scene.json"}, "scene.json")), digest);
  EXPECT_NE(inputFilesDigest(withFiles({"scene.json", "b.png"}, "scene.json")), digest);
  EXPECT_NE(inputFilesDigest(withFiles({"scene.json", "a.png"}, "a.png")), digest);
}

}  // namespace
}  // namespace pathfarm::farm
