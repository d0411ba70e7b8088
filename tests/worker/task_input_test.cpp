// A filter task takes the input frames it changes: moved when it alone holds them (no
// second copy of a large frame), copied when the worker's decoded inputs share them.
#include <gtest/gtest.h>

#include <algorithm>

#include "image/exr_io.h"
#include "postproc/filters/component_upsampler.h"
#include "test_support.h"
#include "postproc/filters/direct_emission.h"
#include "worker/filter_inputs.h"
#include "worker/filter_tasks.h"

namespace pathfarm::farm {
namespace {

std::shared_ptr<FrameImage> frameOf(float value) {
  auto frame = std::make_shared<FrameImage>(4, 3);
  frame->addChannel("R").assign(12, value);
  return frame;
}

TEST(TaskInput, ASoleOwnerMovesTheFrameOutAndASharedOneCopiesIt) {
  TaskInput alone{TASK_ASSEMBLE_FRAME, {}, frameOf(2.0f)};
  const float* planeBefore = alone.image().channel("R").data();
  FrameImage taken = alone.take();
  EXPECT_EQ(taken.channel("R").data(), planeBefore) << "moved, not copied";
  EXPECT_EQ(alone.frame, nullptr);
  EXPECT_THROW(alone.take(), std::logic_error);

  const std::shared_ptr<FrameImage> kept = frameOf(3.0f);  // as the decoded inputs keep one
  TaskInput shared{TASK_ASSEMBLE_FRAME, {}, kept};
  FrameImage copy = shared.take();
  EXPECT_NE(copy.channel("R").data(), kept->channel("R").data());
  copy.channel("R")[0] = 7.0f;
  EXPECT_EQ(kept->channel("R")[0], 3.0f) << "the shared frame is untouched";
}

// A worker's input is decoded when the task first reads it, once.
TEST(TaskInput, AnInputIsDecodedWhenFirstReadAndOnlyOnce) {
  int decodes = 0;
  TaskInput lazy{TASK_ASSEMBLE_FRAME, {}, nullptr, [&] {
                   ++decodes;
                   return frameOf(5.0f);
                 }};
  EXPECT_EQ(decodes, 0);
  EXPECT_EQ(lazy.image().channel("R")[0], 5.0f);
  EXPECT_EQ(lazy.image().channel("R")[1], 5.0f);
  EXPECT_EQ(decodes, 1);
  const FrameImage taken = lazy.take();
  EXPECT_EQ(taken.channel("R")[0], 5.0f);
  EXPECT_EQ(decodes, 1);
  EXPECT_THROW(lazy.image(), std::logic_error);

  TaskInput takenFirst{TASK_ASSEMBLE_FRAME, {}, nullptr, [] { return frameOf(6.0f); }};
  EXPECT_EQ(takenFirst.take().channel("R")[0], 6.0f) << "taking decodes too";
}

// Part of an input: decoded alone while the whole frame is not, copied from it once it is.
TEST(TaskInput, APartIsDecodedAloneUnlessTheWholeFrameIsDecodedAlready) {
  const auto onlyG = [](const std::string& name) { return name == "G"; };
  int wholeDecodes = 0, partDecodes = 0;
  TaskInput input{TASK_ASSEMBLE_FRAME, {}, nullptr, [&] {
                    ++wholeDecodes;
                    auto frame = frameOf(1.0f);
                    frame->addChannel("G").assign(12, 4.0f);
                    return frame;
                  }};
  input.decodePart = [&](const InputPart&) {
    ++partDecodes;
    FrameImage part(4, 3);
    part.addChannel("G").assign(12, 4.0f);
    return part;
  };
  EXPECT_EQ(input.part({onlyG}).channelNames(), std::vector<std::string>{"G"});
  EXPECT_EQ(partDecodes, 1);
  EXPECT_EQ(wholeDecodes, 0);
  input.image();
  const FrameImage copied = input.part({onlyG});
  EXPECT_EQ(partDecodes, 1);
  EXPECT_EQ(copied.channelNames(), std::vector<std::string>{"G"});
  EXPECT_EQ(copied.channel("G")[11], 4.0f);
  EXPECT_TRUE(input.image().hasChannel("R")) << "the input keeps its frame";
}

// Rows of a decoded frame are cut from it; rows outside it are refused, not read past.
TEST(TaskInput, RowsOfADecodedFrameAreThoseRowsOfTheChannelsKept) {
  FrameImage frame(3, 4);
  std::vector<float>& r = frame.addChannel("R");
  for (size_t p = 0; p < r.size(); ++p) r[p] = static_cast<float>(p);
  frame.addChannel("G").assign(12, 2.0f);
  frame.attributes()["a"] = "b";
  TaskInput input{TASK_UPSAMPLE, {}, std::make_shared<FrameImage>(frame)};
  const FrameImage rows = input.part({[](const std::string& name) { return name == "R"; }, 1, 3});
  ASSERT_EQ(rows.width(), 3);
  ASSERT_EQ(rows.height(), 2);
  EXPECT_EQ(rows.channelNames(), std::vector<std::string>{"R"});
  EXPECT_EQ(rows.channel("R"), (std::vector<float>{3, 4, 5, 6, 7, 8}));
  EXPECT_EQ(rows.attributes().at("a"), "b");
  EXPECT_THROW(input.part({{}, 2, 5}), std::runtime_error);
  EXPECT_THROW(input.part({{}, 3, 3}), std::runtime_error);
}

// A render reduced a strip of rows at a time, each strip decoded alone from its file, is
// the bits of the whole frame without its light, box-downsampled at once.
TEST(TaskInput, ARenderReducedStripByStripIsTheWholeFrameReduced) {
  constexpr int kSize = 136;  // strips of 64, 64 and 8 rows
  const FrameImage render = test_support::renderDecomposed("scenes/cornell/scene.json", kSize, kSize, 2, 0);
  const auto file = test_support::processTemporaryFolder("pathfarm_reduce") / "render.exr";
  writeExr(file, render);
  TaskInput input{TASK_ASSEMBLE_FRAME, {}, nullptr, [] () -> std::shared_ptr<FrameImage> {
                    throw std::logic_error("decoded whole");
                  }};
  int strips = 0;
  input.decodePart = [&](const InputPart& wanted) {
    ++strips;
    EXPECT_LE(wanted.endRow - wanted.firstRow, 64);
    return readExrRows(file, "render", wanted.firstRow, wanted.endRow, wanted.keep);
  };
  const FrameImage reduced = reducedWithoutLight(input, kSize, kSize, 2);
  EXPECT_EQ(strips, 3);
  FrameImage whole = render;
  ASSERT_GT(directEmissionOf(whole).channelNames().size(), 0u) << "the lamp is seen: light is taken out";
  takeDirectEmission(whole);
  const FrameImage expected = boxDownsample(whole, 2);
  std::vector<std::string> names = reduced.channelNames(), expectedNames = expected.channelNames();
  std::sort(names.begin(), names.end());  // a file's channels are in alphabetical order
  std::sort(expectedNames.begin(), expectedNames.end());
  ASSERT_EQ(names, expectedNames);
  for (const std::string& name : expected.channelNames())
    EXPECT_TRUE(reduced.channel(name) == expected.channel(name)) << name;
  EXPECT_EQ(reduced.attributes(), expected.attributes());
}

}  // namespace
}  // namespace pathfarm::farm
