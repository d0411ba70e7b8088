// Decoded inputs are kept within their budget, least recently used out first, and a
// worker decodes a chunk many tasks read once; a chunk it refused is refused every time.
#include "worker/decoded_inputs.h"

#include <gtest/gtest.h>

#include <limits>
#include <map>

#include "image/exr_io.h"
#include "worker/task_runner.h"

namespace pathfarm::farm {
namespace {

// A frame of `channels` planes of 10x10 pixels: 400 bytes of floats each.
std::shared_ptr<const FrameImage> planes(int channels, float value = 1.0f) {
  auto frame = std::make_shared<FrameImage>(10, 10);
  for (int c = 0; c < channels; ++c) frame->addChannel("c" + std::to_string(c)).assign(100, value);
  return frame;
}

const uint64_t kOnePlane = DecodedInputs::frameBytes(*planes(1));

TEST(DecodedInputs, KeepsTheMostRecentlyUsedWithinTheBudget) {
  DecodedInputs kept(3 * kOnePlane);  // three one-plane frames
  kept.keep("a", planes(1));
  kept.keep("b", planes(1));
  kept.keep("c", planes(1));
  EXPECT_EQ(kept.bytes(), 3 * kOnePlane);
  ASSERT_NE(kept.find("a"), nullptr);  // "a" is now the most recent; "b" the least
  kept.keep("d", planes(1));
  EXPECT_EQ(kept.find("b"), nullptr);
  EXPECT_NE(kept.find("a"), nullptr);
  EXPECT_NE(kept.find("c"), nullptr);
  EXPECT_NE(kept.find("d"), nullptr);
  // A two-plane frame pushes out the two least recent.
  kept.keep("e", planes(2));
  EXPECT_EQ(kept.size(), 2u);
  EXPECT_NE(kept.find("d"), nullptr);
  EXPECT_NE(kept.find("e"), nullptr);
  EXPECT_EQ(kept.bytes(), kOnePlane + DecodedInputs::frameBytes(*planes(2)));
}

// An 8-pixel tile's floats are a small part of what keeping it costs: a budget counted in
// floats alone let a worker reading millions of tiles hold three times its budget.
TEST(DecodedInputs, TinyFramesCountWhatKeepingThemCosts) {
  auto tile = std::make_shared<FrameImage>(1, 1);
  for (const char* name : {"R", "G", "B"}) tile->addChannel(name);
  tile->attributes()["pathfarm.frame"] = "12";
  // Their floats are 12 bytes, but every frame holds at least its three vectors, their
  // names twice, an attribute, and the entry's own nodes and digest.
  const uint64_t atLeast = 3 * (sizeof(std::vector<float>) + 2 * sizeof(std::string)) + 2 * sizeof(std::string) +
                           sizeof(FrameImage) + 64;
  EXPECT_GE(DecodedInputs::frameBytes(*tile), atLeast);
  DecodedInputs kept(1'000'000);
  for (int i = 0; i < 10'000; ++i) kept.keep(std::to_string(i), tile);
  EXPECT_LE(kept.size() * atLeast, 1'000'000u);
  EXPECT_LE(kept.bytes(), 1'000'000u);
}

TEST(DecodedInputs, AFrameLargerThanTheBudgetIsNotKeptAndEvictsNothing) {
  DecodedInputs kept(2 * kOnePlane);
  kept.keep("small", planes(1));
  kept.keep("large", planes(3));
  EXPECT_EQ(kept.find("large"), nullptr);
  EXPECT_NE(kept.find("small"), nullptr);
  DecodedInputs none(0);
  none.keep("small", planes(1));
  EXPECT_EQ(none.size(), 0u);
}

// Composite leases of frame 3 whose only input is the upsampled keyframe `chunk` (no pixel
// re-rendered): each one's output is that frame's colors.
Lease compositeLease() {
  Lease lease;
  lease.set_kind(TASK_COMPOSITE);
  lease.mutable_spec()->set_pipeline(PIPELINE_DU);
  lease.mutable_spec()->set_width(4);
  lease.mutable_spec()->set_height(2);
  lease.mutable_params()->set_frame(3);
  lease.add_inputs()->set_sha256("keyframe");
  lease.add_input_kinds(TASK_UPSAMPLE);
  lease.add_input_params()->set_frame(3);
  return lease;
}

FrameImage keyframe(float value) {
  FrameImage frame(4, 2);
  for (const char* c : {"R", "G", "B"}) frame.addChannel(c).assign(frame.pixelCount(), value);
  return frame;
}

FrameImage runComposite(TaskRunner& runner, const std::string& chunk, int& fetches) {
  std::atomic<double> progress{0};
  std::atomic<bool> abandon{false};
  const TaskOutput output = runner.run(
      compositeLease(),
      [&](const ChunkRef&) {
        ++fetches;
        return chunk;
      },
      progress, abandon);
  return decodeExr(output.chunk, "composite");
}

TEST(DecodedInputs, AWorkerDecodesAChunkTwoTasksReadOnce) {
  TaskRunner runner(1, std::filesystem::temp_directory_path() / "pathfarm_decoded_inputs_scenes",
                    std::filesystem::temp_directory_path() / "pathfarm_decoded_inputs_outgoing");
  const std::string chunk = encodeExr(keyframe(0.25f), ExrCompression::Fast);
  int fetches = 0;
  EXPECT_EQ(runComposite(runner, chunk, fetches).channel("G"), std::vector<float>(8, 0.25f));
  EXPECT_EQ(runComposite(runner, chunk, fetches).channel("G"), std::vector<float>(8, 0.25f));
  EXPECT_EQ(fetches, 1);

  TaskRunner forgetful(1, std::filesystem::temp_directory_path() / "pathfarm_decoded_inputs_scenes",
                    std::filesystem::temp_directory_path() / "pathfarm_decoded_inputs_outgoing", 0);
  fetches = 0;
  runComposite(forgetful, chunk, fetches);
  runComposite(forgetful, chunk, fetches);
  EXPECT_EQ(fetches, 2);
}

TEST(DecodedInputs, AChunkHoldingANanIsRefusedEveryTime) {
  TaskRunner runner(1, std::filesystem::temp_directory_path() / "pathfarm_decoded_inputs_scenes",
                    std::filesystem::temp_directory_path() / "pathfarm_decoded_inputs_outgoing");
  FrameImage poisoned = keyframe(0.25f);
  poisoned.channel("B")[5] = std::numeric_limits<float>::quiet_NaN();
  const std::string chunk = encodeExr(poisoned, ExrCompression::Fast);
  for (int attempt = 0; attempt < 2; ++attempt) {
    int fetches = 0;
    try {
      runComposite(runner, chunk, fetches);
      FAIL() << "attempt " << attempt << " used a chunk with a NaN";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("input chunk keyframe holds a non-finite value (channel B at pixel (1, 1))"),
                std::string::npos)
          << e.what();
    }
    EXPECT_EQ(fetches, 1) << "attempt " << attempt;
  }
}

}  // namespace
}  // namespace pathfarm::farm
