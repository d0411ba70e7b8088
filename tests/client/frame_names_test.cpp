// Frame names from a template: fields expanded and padded, bad templates refused, and
// fetched frames moved to their names.
#include <gtest/gtest.h>

#include <fstream>

#include "client/frame_names.h"
#include "test_support.h"

namespace pathfarm::farm {
namespace {

TEST(FrameNames, FieldsAreExpandedAndPadded) {
  EXPECT_EQ(FrameNames("{shot}/{frame:04d}.exr").nameOf(12, "dolly", 3), "dolly/0012.exr");
  EXPECT_EQ(FrameNames("shot{id}_{frame}.exr").nameOf(7, "x", 41), "shot41_7.exr");
  EXPECT_EQ(FrameNames("{frame:02d}.exr").nameOf(1234, "x", 1), "1234.exr");  // padding never truncates
}

TEST(FrameNames, BadTemplatesAreRefusedSayingWhy) {
  const auto refusal = [](const std::string& pattern) {
    try {
      FrameNames{pattern};
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_NE(refusal("{shot}.exr").find("needs {frame}"), std::string::npos);
  EXPECT_NE(refusal("{frame}/{scene}.exr").find("unknown field {scene}"), std::string::npos);
  EXPECT_NE(refusal("{frame:4d}.exr").find("unknown field {frame:4d}"), std::string::npos);
  EXPECT_NE(refusal("{frame.exr").find("without its '}'"), std::string::npos);
  EXPECT_NE(refusal("/tmp/{frame}.exr").find("relative"), std::string::npos);
  EXPECT_NE(refusal("../{frame}.exr").find(".."), std::string::npos);
}

TEST(FrameNames, FetchedFramesMoveToTheirNames) {
  const auto folder = test_support::processTemporaryFolder("pathfarm_frame_names");
  std::filesystem::create_directories(folder);
  std::vector<std::filesystem::path> frames;
  for (const char* name : {"frame_0003.exr", "frame_0004.exr"}) {
    frames.push_back(folder / name);
    std::ofstream(frames.back()) << name;
  }
  const auto renamed = renameFrames(frames, folder, FrameNames("{shot}/v{id}.{frame:03d}.exr"), "walk", 2);
  ASSERT_EQ(renamed.size(), 2u);
  EXPECT_EQ(renamed[1], folder / "walk" / "v2.004.exr");
  std::ifstream moved(renamed[0]);
  std::string text;
  moved >> text;
  EXPECT_EQ(text, "frame_0003.exr");
  EXPECT_FALSE(std::filesystem::exists(frames[0]));
}

}  // namespace
}  // namespace pathfarm::farm
