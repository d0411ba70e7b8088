// What the scheduler refuses of a task's output: bytes that are no EXR, a non-finite
// value, a tile that is not its window's size, an image larger than the shot's frame.
#include "scheduler/output_check.h"

#include <gtest/gtest.h>

#include <fstream>
#include <limits>

#include "image/exr_io.h"
#include "test_support.h"

namespace pathfarm::farm {
namespace {

std::string imageBytes(int width, int height, float corner = 1.0f) {
  FrameImage image(width, height);
  for (const char* channel : {"R", "G", "B"}) image.addChannel(channel).assign(image.pixelCount(), 0.5f);
  image.channel("B")[image.pixelCount() - 1] = corner;
  return encodeExr(image, ExrCompression::Fast);
}

// The bytes in a file, as the store keeps an output.
std::filesystem::path stored(const std::string& bytes) {
  const std::filesystem::path file = test_support::processTemporaryFolder("pathfarm_output_check") / "output";
  std::ofstream(file, std::ios::binary) << bytes;
  return file;
}

struct OutputCheck : ::testing::Test {
  OutputCheck() {
    spec.set_width(64);
    spec.set_height(32);
    tile.mutable_window()->set_x0(32);
    tile.mutable_window()->set_x1(64);
    tile.mutable_window()->set_y0(0);
    tile.mutable_window()->set_y1(32);
  }
  ShotSpec spec;
  TaskParams tile, none;
};

TEST_F(OutputCheck, ASoundTileOrFrameIsTaken) {
  EXPECT_EQ(refusalOfOutput(stored(imageBytes(32, 32)), TASK_RENDER_TILE, tile, spec), "");
  EXPECT_EQ(refusalOfOutput(stored(imageBytes(64, 32)), TASK_ASSEMBLE_FRAME, none, spec), "");
  EXPECT_EQ(refusalOfOutput(stored(imageBytes(32, 16)), TASK_DENOISE, none, spec), "") << "a keyframe at half resolution";
}

TEST_F(OutputCheck, NonFiniteValuesAreRefusedWhereTheyAre) {
  const float infinity = std::numeric_limits<float>::infinity();
  EXPECT_EQ(refusalOfOutput(stored(imageBytes(32, 32, infinity)), TASK_RENDER_TILE, tile, spec),
            "a non-finite value in channel B at pixel (31, 31)");
  EXPECT_NE(refusalOfOutput(stored(imageBytes(64, 32, std::numeric_limits<float>::quiet_NaN())), TASK_COMPOSITE, none, spec),
            "");
}

TEST_F(OutputCheck, SizesThatDoNotFitAreRefused) {
  EXPECT_EQ(refusalOfOutput(stored(imageBytes(33, 32)), TASK_RENDER_TILE, tile, spec), "the tile is 33x32, its window 32x32");
  EXPECT_EQ(refusalOfOutput(stored(imageBytes(64, 64)), TASK_INTERPOLATE, none, spec),
            "the image is 64x64, larger than the shot's 64x32 frame");
}

TEST_F(OutputCheck, BytesThatAreNoImageAreRefusedButOutputsThatAreNoImageAreNotRead) {
  EXPECT_NE(refusalOfOutput(stored("not an EXR file"), TASK_RENDER_TILE, tile, spec), "");
  EXPECT_EQ(refusalOfOutput(stored(""), TASK_NOOP, none, spec), "");
  EXPECT_EQ(refusalOfOutput(stored("{\"relmse\": 0.1}"), TASK_EVALUATE, none, spec), "");
}

}  // namespace
}  // namespace pathfarm::farm
