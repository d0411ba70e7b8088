// A filter task takes the input frames it changes: moved when it alone holds them (no
// second copy of a large frame), copied when the worker's decoded inputs share them.
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace pathfarm::farm
