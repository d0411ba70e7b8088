// Multi-layer EXR frames survive a write and a read unchanged; broken files are errors.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <limits>
#include <random>

#include "image/exr_io.h"

namespace pathfarm {
namespace {

std::filesystem::path temporaryFile(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("pathfarm_exr_" + name);
}

FrameImage sampleFrame() {
  FrameImage frame(37, 23);  // odd sizes catch stride mistakes
  std::mt19937 random(5);
  std::normal_distribution<float> value(0.0f, 10.0f);
  for (const char* name : {"R", "G", "B", "diffuse_direct.color.R", "diffuse_direct.reflectance.G",
                           "reflection.normal.Z", "transmission.motion.X", "depth.Z"}) {
    for (float& v : frame.addChannel(name)) v = value(random);
  }
  frame.channel("depth.Z")[5] = std::numeric_limits<float>::infinity();
  frame.attributes()["pathfarm.frame"] = "12";
  frame.attributes()["pathfarm.decomposition"] = "diffuse_direct=ED,residual";
  return frame;
}

TEST(ExrIo, MultiLayerRoundTripIsExact) {
  const FrameImage original = sampleFrame();
  const auto file = temporaryFile("roundtrip.exr");
  writeExr(file, original);
  const FrameImage loaded = readExr(file);
  EXPECT_EQ(loaded.width(), original.width());
  EXPECT_EQ(loaded.height(), original.height());
  ASSERT_EQ(loaded.channelNames().size(), original.channelNames().size());
  for (const std::string& name : original.channelNames()) {
    ASSERT_TRUE(loaded.hasChannel(name)) << name;
    EXPECT_EQ(loaded.channel(name), original.channel(name)) << name;
  }
  EXPECT_EQ(loaded.attributes().at("pathfarm.frame"), "12");
  EXPECT_EQ(loaded.attributes().at("pathfarm.decomposition"), "diffuse_direct=ED,residual");
  for (const auto& entry : std::filesystem::directory_iterator(file.parent_path()))
    EXPECT_EQ(entry.path().string().find(file.string() + "."), std::string::npos) << "left behind: " << entry.path();
  std::filesystem::remove(file);
}

TEST(ExrIo, MissingAndTruncatedFilesAreErrorsNamingTheFile) {
  EXPECT_THROW(readExr(temporaryFile("does_not_exist.exr")), ExrError);
  const auto file = temporaryFile("truncated.exr");
  writeExr(file, sampleFrame());
  const auto size = std::filesystem::file_size(file);
  for (const auto keep : {size / 2, size_t{300}, size_t{10}, size_t{0}}) {
    std::filesystem::resize_file(file, keep);
    try {
      readExr(file);
      FAIL() << "a file truncated to " << keep << " bytes was read";
    } catch (const ExrError& e) {
      EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos);
    }
  }
  std::filesystem::remove(file);
}

TEST(ExrIo, BytesInMemoryMatchTheFile) {
  const FrameImage original = sampleFrame();
  const auto file = temporaryFile("memory.exr");
  writeExr(file, original);
  std::ifstream in(file, std::ios::binary);
  const std::string onDisk{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  EXPECT_EQ(encodeExr(original), onDisk);
  EXPECT_EQ(decodeExr(onDisk, "chunk").channel("reflection.normal.Z"), original.channel("reflection.normal.Z"));
  std::string damaged = onDisk;
  damaged.resize(damaged.size() / 3);
  try {
    decodeExr(damaged, "chunk 1f2e");
    FAIL() << "damaged bytes were decoded";
  } catch (const ExrError& e) {
    EXPECT_NE(std::string(e.what()).find("chunk 1f2e"), std::string::npos);
  }
  std::filesystem::remove(file);
}

TEST(ExrIo, PasteCopiesAPartIntoItsPlace) {
  FrameImage frame(4, 3), part(2, 2);
  part.addChannel("R") = {1, 2, 3, 4};
  frame.paste(part, 2, 1);
  EXPECT_EQ(frame.channel("R"), (std::vector<float>{0, 0, 0, 0, 0, 0, 1, 2, 0, 0, 3, 4}));
  EXPECT_THROW(frame.paste(part, 3, 1), std::invalid_argument);
}

TEST(ExrIo, MissingChannelIsAClearError) {
  const FrameImage frame = sampleFrame();
  try {
    frame.channel("emission.color.R");
    FAIL();
  } catch (const std::out_of_range& e) {
    EXPECT_NE(std::string(e.what()).find("emission.color.R"), std::string::npos);
  }
}

}  // namespace
}  // namespace pathfarm
