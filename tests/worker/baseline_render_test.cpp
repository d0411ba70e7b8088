// A shot's baseline renders of one frame (ShotSpec.baseline_repeats) are the parts of one
// longer render: the n-th takes the n-th range of spp samples, so n renders together are
// the render at n x spp, and no two share a sample.
#include <gtest/gtest.h>

#include <atomic>

#include "image/exr_io.h"
#include "test_support.h"
#include "worker/task_runner.h"

namespace pathfarm::farm {
namespace {

constexpr int kBaselineSize = 16;

// Plain pt of frame 1 of the Cornell box at `spp`, rendered by a worker as the `repeat`-th
// baseline render of the frame.
FrameImage baselineRender(TaskRunner& runner, int spp, int repeat) {
  Lease lease;
  lease.set_kind(TASK_RENDER_TILE);
  lease.set_shot_id(1);
  ShotSpec& spec = *lease.mutable_spec();
  spec.set_scene((test_support::sourceDir() / "scenes/cornell/scene.json").string());
  spec.set_pipeline(PIPELINE_D);
  spec.set_width(kBaselineSize);
  spec.set_height(kBaselineSize);
  spec.set_spp(spp);
  spec.set_max_depth(4);
  TaskParams& params = *lease.mutable_params();
  params.set_frame(1);
  params.set_role(ROLE_BASELINE);
  params.set_beauty_only(true);
  params.set_baseline_repeat(repeat);
  params.set_spp(spp);  // as planned: the shot's renderer is kept between its tasks
  PixelWindow& window = *params.mutable_window();
  window.set_x1(kBaselineSize);
  window.set_y1(kBaselineSize);
  std::atomic<double> progress{0};
  std::atomic<bool> abandon{false};
  const TaskOutput output = runner.run(lease, [](const ChunkRef&) { return std::string(); }, progress, abandon);
  return decodeExr(output.chunk, "baseline render");
}

TEST(BaselineRender, TheNthRenderTakesTheNthRangeOfSamples) {
  TaskRunner runner(1, test_support::processTemporaryFolder("pathfarm_baseline_scenes"),
                    test_support::processTemporaryFolder("pathfarm_baseline_outgoing"));
  const FrameImage first = baselineRender(runner, 4, 0), second = baselineRender(runner, 4, 1);
  const FrameImage both = baselineRender(runner, 8, 0);
  double difference = 0;
  for (const char* channel : {"R", "G", "B"})
    for (size_t p = 0; p < both.pixelCount(); ++p) {
      const float a = first.channel(channel)[p], b = second.channel(channel)[p];
      const float whole = both.channel(channel)[p];
      EXPECT_NEAR(0.5f * (a + b), whole, 1e-4f * (1.0f + whole)) << channel << " pixel " << p;
      difference += std::abs(a - b);
    }
  // Not the same samples twice: the two renders differ.
  EXPECT_GT(difference, 0.0);
}

}  // namespace
}  // namespace pathfarm::farm
