// The assembly of a frame from its tiles trusts nothing it fetched: a tile of the wrong
// size or holding a NaN is refused with a reason (the attempt fails) instead of being
// pasted into the frame; good tiles make the frame.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <random>

#include "image/exr_io.h"
#include "test_support.h"
#include "worker/assemble_frame.h"
#include "worker/failure_class.h"
#include "worker/task_runner.h"

namespace pathfarm::farm {
namespace {

// A tile of the window's size with a constant beauty, as a renderer's chunk would be.
FrameImage tile(int width, int height, float value) {
  FrameImage image(width, height);
  for (const char* c : {"R", "G", "B"}) image.addChannel(c).assign(image.pixelCount(), value);
  image.attributes()["pathfarm.nonfinite_samples"] = "0";
  return image;
}

struct Assembly {
  Lease lease;
  std::map<std::string, std::string> chunks;  // by digest

  Assembly() {
    lease.set_kind(TASK_ASSEMBLE_FRAME);
    lease.mutable_spec()->set_width(4);
    lease.mutable_spec()->set_height(2);
  }
  // Adds the tile covering [x0, x0 + 2) x [0, 2).
  void add(int x0, const FrameImage& image) {
    const std::string name = "tile" + std::to_string(x0);
    chunks[name] = encodeExr(image, ExrCompression::Fast);
    lease.add_inputs()->set_sha256(name);
    TaskParams* params = lease.add_input_params();
    params->mutable_window()->set_x0(x0);
    params->mutable_window()->set_y0(0);
    params->mutable_window()->set_x1(x0 + 2);
    params->mutable_window()->set_y1(2);
    lease.add_input_kinds(TASK_RENDER_TILE);
  }
  // The frame, through the worker's task runner, the tiles given as bytes; its file is
  // gone once the output is.
  FrameImage run() {
    const auto folder = test_support::processTemporaryFolder("pathfarm_assemble");
    TaskRunner runner(1, folder / "scenes", folder / "outgoing");  // no scene is read
    std::atomic<double> progress{0};
    std::atomic<bool> abandon{false};
    std::filesystem::path file;
    FrameImage frame;
    {
      const TaskOutput output =
          runner.run(lease, [&](const ChunkRef& ref) { return chunks.at(ref.sha256()); }, progress, abandon);
      EXPECT_TRUE(output.chunk.empty());
      file = output.chunkFile->path();
      EXPECT_EQ(file.parent_path(), folder / "outgoing");
      frame = readExr(file);
      EXPECT_EQ(progress, 1.0);
    }
    EXPECT_FALSE(std::filesystem::exists(file));
    EXPECT_TRUE(std::filesystem::is_empty(folder / "outgoing"));  // nor the tiles' scratch files
    return frame;
  }
};

TEST(AssembleFrame, GoodTilesMakeTheFrame) {
  Assembly assembly;
  assembly.add(0, tile(2, 2, 1.0f));
  assembly.add(2, tile(2, 2, 2.0f));
  const FrameImage frame = assembly.run();
  EXPECT_EQ(frame.channel("R"), (std::vector<float>{1, 1, 2, 2, 1, 1, 2, 2}));
}

TEST(AssembleFrame, ATileHoldingANanIsRefusedNotPasted) {
  Assembly assembly;
  assembly.add(0, tile(2, 2, 1.0f));
  FrameImage poisoned = tile(2, 2, 2.0f);
  poisoned.channel("G")[3] = std::numeric_limits<float>::quiet_NaN();
  assembly.add(2, poisoned);
  try {
    assembly.run();
    FAIL() << "a tile with a NaN was pasted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("tile chunk tile2 holds a non-finite value (channel G at pixel (1, 1))"),
              std::string::npos)
        << e.what();
  }
}

// Good tiles and a frame file that cannot be written (its folder is gone): the worker's
// disk failed, not the task's input, so the task is not charged with bad input.
TEST(AssembleFrame, AFrameThatCannotBeWrittenIsTheWorkersFaultNotTheInputs) {
  Assembly assembly;
  assembly.add(0, tile(2, 2, 1.0f));
  assembly.add(2, tile(2, 2, 2.0f));
  const auto folder = test_support::processTemporaryFolder("pathfarm_assemble_unwritable");
  const auto fetch = [&](const ChunkRef& ref) {
    const std::filesystem::path file = folder / (ref.sha256() + ".exr");
    std::ofstream(file, std::ios::binary) << assembly.chunks.at(ref.sha256());
    return file;
  };
  std::atomic<double> progress{0};
  try {
    assembleFrame(assembly.lease, fetch, folder / "gone" / "frame.exr", progress);
    FAIL() << "a frame was written into a folder that does not exist";
  } catch (const std::exception& e) {
    EXPECT_EQ(classifyFailure(e), FAILURE_WORKER_FAULT) << e.what();
    EXPECT_NE(std::string(e.what()).find("cannot write the task's output"), std::string::npos) << e.what();
  }
}

TEST(AssembleFrame, ARegionIsAssembledAtItsWindowAndRegionsMakeTheFrame) {
  // The frame's right half as a region of its own (a large frame's first step).
  Assembly region;
  region.lease.mutable_params()->mutable_window()->set_x0(2);
  region.lease.mutable_params()->mutable_window()->set_x1(4);
  region.lease.mutable_params()->mutable_window()->set_y1(2);
  region.add(2, tile(2, 2, 2.0f));
  const FrameImage right = region.run();
  ASSERT_EQ(right.width(), 2);
  EXPECT_EQ(right.channel("R"), (std::vector<float>{2, 2, 2, 2}));
  // A tile outside the region is refused.
  Assembly outside = region;
  outside.add(0, tile(2, 2, 1.0f));
  EXPECT_THROW(outside.run(), std::runtime_error);

  // The frame from its regions, as from tiles.
  Assembly frame;
  frame.add(0, tile(2, 2, 1.0f));
  FrameImage rightRegion = right;
  frame.add(2, rightRegion);
  EXPECT_EQ(frame.run().channel("R"), (std::vector<float>{1, 1, 2, 2, 1, 1, 2, 2}));
}

TEST(AssembleFrame, ATileOfTheWrongSizeIsRefused) {
  Assembly assembly;
  assembly.add(0, tile(2, 1, 1.0f));
  EXPECT_THROW(assembly.run(), std::runtime_error);
}

// A 150 x 140 frame in 40 x 48 tiles (short at the right and bottom edges) crosses several
// strips and tiles several of them; one tile has a channel the others lack.
struct UnevenTiles {
  Lease lease;
  std::map<std::string, std::filesystem::path> files;  // the tiles' chunks, by digest
  FrameImage expected{150, 140};                       // the tiles pasted into a whole frame
  int fetches = 0;

  UnevenTiles() {
    lease.set_kind(TASK_ASSEMBLE_FRAME);
    lease.mutable_spec()->set_width(150);
    lease.mutable_spec()->set_height(140);
    const auto folder = test_support::processTemporaryFolder("pathfarm_assemble") / "uneven";
    std::filesystem::create_directories(folder);
    std::mt19937 random(7);
    std::uniform_real_distribution<float> value(0.0f, 4.0f);
    uint64_t dropped = 0;
    for (int y0 = 0; y0 < 140; y0 += 48) {
      for (int x0 = 0; x0 < 150; x0 += 40) {
        FrameImage part = tile(std::min(40, 150 - x0), std::min(48, 140 - y0), 0.0f);
        for (const char* c : {"R", "G", "B"})
          for (float& v : part.channel(c)) v = value(random);
        if (x0 == 40 && y0 == 48) part.addChannel("Z").assign(part.pixelCount(), 9.0f);
        part.attributes()["pathfarm.nonfinite_samples"] = std::to_string(x0 + y0);
        part.attributes()["pathfarm.tile"] = std::to_string(x0) + "," + std::to_string(y0);
        dropped += static_cast<uint64_t>(x0 + y0);
        const std::string name = "tile" + std::to_string(files.size());
        files[name] = folder / (name + ".exr");
        std::ofstream(files[name], std::ios::binary) << encodeExr(part, ExrCompression::Fast);
        lease.add_inputs()->set_sha256(name);
        PixelWindow* window = lease.add_input_params()->mutable_window();
        window->set_x0(x0);
        window->set_y0(y0);
        window->set_x1(x0 + part.width());
        window->set_y1(y0 + part.height());
        lease.add_input_kinds(TASK_RENDER_TILE);
        expected.paste(part, x0, y0);
        expected.attributes() = part.attributes();
      }
    }
    expected.attributes()["pathfarm.nonfinite_samples"] = std::to_string(dropped);
  }
  std::string assemble() {
    const auto file = test_support::processTemporaryFolder("pathfarm_assemble") / "uneven.exr";
    std::atomic<double> progress{0};
    assembleFrame(
        lease,
        [&](const ChunkRef& ref) {
          ++fetches;
          return files.at(ref.sha256());
        },
        file, progress);
    EXPECT_EQ(progress, 1.0);
    std::ifstream in(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
};

TEST(AssembleFrame, AFrameWrittenInStripsFromTilesReadInPlaceIsTheFileOfTheTilesPastedWhole) {
  UnevenTiles tiles;
  EXPECT_EQ(tiles.assemble(), encodeExr(tiles.expected, ExrCompression::Small));
  EXPECT_EQ(tiles.fetches, static_cast<int>(tiles.files.size()));  // each tile's file asked for once
}

TEST(AssembleFrame, ANanInALaterStripOfATileIsFoundWithItsRowInTheTile) {
  UnevenTiles tiles;
  // tile9 lies at (40, 96), 40 x 44: its rows 0 to 31 go in the strip that ends at row 128,
  // the rest in the next.
  FrameImage poisoned = readExr(tiles.files.at("tile9"));
  poisoned.channel("B")[40 * 40 + 3] = std::numeric_limits<float>::infinity();
  std::ofstream(tiles.files.at("tile9"), std::ios::binary | std::ios::trunc) << encodeExr(poisoned);
  try {
    tiles.assemble();
    FAIL() << "a tile with an infinity was pasted";
  } catch (const BadInput& e) {
    EXPECT_NE(std::string(e.what()).find("tile chunk tile9 holds a non-finite value (channel B at pixel (3, 40))"),
              std::string::npos)
        << e.what();
  }
}

TEST(FrameImageCheck, FirstNonFiniteNamesTheChannelAndPixel) {
  FrameImage image = tile(3, 2, 0.5f);
  EXPECT_EQ(image.firstNonFinite(), "");
  image.channel("B")[4] = std::numeric_limits<float>::infinity();
  EXPECT_EQ(image.firstNonFinite(), "channel B at pixel (1, 1)");
}

// A reference from the client's cache (TaskParams.given_frame) is handed on as its bytes
// when it is a frame of the shot; one of another size, without a beauty or holding a NaN
// is refused with a reason.
TEST(AssembleFrame, AGivenReferenceIsCheckedAndHandedOnAsItIs) {
  const auto handOn = [](const FrameImage& given) {
    Lease lease;
    lease.set_kind(TASK_ASSEMBLE_FRAME);
    lease.mutable_spec()->set_width(4);
    lease.mutable_spec()->set_height(2);
    lease.mutable_params()->set_frame(7);
    lease.mutable_params()->set_role(ROLE_REFERENCE);
    lease.mutable_params()->mutable_given_frame()->set_sha256("given");
    const std::string bytes = encodeExr(given, ExrCompression::Fast);
    const auto folder = test_support::processTemporaryFolder("pathfarm_given");
    TaskRunner runner(1, folder / "scenes", folder / "outgoing");
    std::atomic<double> progress{0};
    std::atomic<bool> abandon{false};
    const TaskOutput output = runner.run(
        lease, [&](const ChunkRef& ref) { return ref.sha256() == "given" ? bytes : std::string(); }, progress, abandon);
    EXPECT_EQ(output.chunk, bytes);
  };
  handOn(tile(4, 2, 0.5f));

  const auto refusal = [&](const FrameImage& given) {
    try {
      handOn(given);
    } catch (const BadInput& e) {
      return std::string(e.what());
    } catch (const std::exception& e) {
      return "not BadInput: " + std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(refusal(tile(2, 2, 0.5f)), "the cached reference of frame 7 is 2x2, the shot renders 4x2");
  FrameImage noBeauty(4, 2);
  noBeauty.addChannel("Y");
  EXPECT_NE(refusal(noBeauty).find("has no channel \"R\""), std::string::npos) << refusal(noBeauty);
  FrameImage poisoned = tile(4, 2, 0.5f);
  poisoned.channel("B")[5] = std::numeric_limits<float>::infinity();
  EXPECT_NE(refusal(poisoned).find("holds a non-finite value"), std::string::npos) << refusal(poisoned);
}

}  // namespace
}  // namespace pathfarm::farm
