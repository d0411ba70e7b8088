// A frame of more tiles than one assemble task may read is assembled in two steps:
// blocks of tiles into regions, regions into the frame. Every tile lands in exactly one
// region, the regions tile the frame, and no assemble task reads more than
// kMaxAssemblyInputs inputs. A filtering shot's frame taller than a filter window is
// upsampled, interpolated and composited window by window in the same way.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <utility>
#include <vector>

#include "scheduler/planner.h"

namespace pathfarm::farm {
namespace {

ShotSpec bigFrame(int width, int height, int tile) {
  ShotSpec spec;
  spec.set_pipeline(PIPELINE_PT);
  spec.set_width(width);
  spec.set_height(height);
  spec.set_spp(1);
  spec.set_tile(tile);
  return spec;
}

// Checks the plan of one frame: returns the number of regions.
size_t checkRegions(const ShotSpec& spec) {
  const std::vector<PlannedTask> plan = planShot(spec);
  const PlannedTask& frame = plan.back();
  EXPECT_EQ(frame.kind, TASK_ASSEMBLE_FRAME);
  EXPECT_FALSE(frame.params.has_window());
  EXPECT_TRUE(frame.output);
  std::vector<int> regionOf(static_cast<size_t>(spec.width()) * static_cast<size_t>(spec.height()), 0);
  size_t regions = 0, tiles = 0;
  for (const size_t index : frame.dependencies) {
    const PlannedTask& region = plan[index];
    EXPECT_EQ(region.kind, TASK_ASSEMBLE_FRAME);
    EXPECT_FALSE(region.output);
    EXPECT_LE(static_cast<int64_t>(region.dependencies.size()), kMaxAssemblyInputs);
    const PixelWindow& area = region.params.window();
    ++regions;
    for (const size_t t : region.dependencies) {
      const PixelWindow& w = plan[t].params.window();
      EXPECT_EQ(plan[t].kind, TASK_RENDER_TILE);
      EXPECT_TRUE(w.x0() >= area.x0() && w.y0() >= area.y0() && w.x1() <= area.x1() && w.y1() <= area.y1());
      for (int y = w.y0(); y < w.y1(); ++y)
        for (int x = w.x0(); x < w.x1(); ++x) ++regionOf[static_cast<size_t>(y) * spec.width() + x];
      ++tiles;
    }
  }
  EXPECT_LE(static_cast<int64_t>(frame.dependencies.size()), kMaxAssemblyInputs);
  EXPECT_EQ(plan.size(), tiles + regions + 1);
  for (const int covered : regionOf) EXPECT_EQ(covered, 1);
  return regions;
}

TEST(PlannerRegions, AFrameOfMoreTilesThanAnAssemblyReadsIsAssembledInRegions) {
  // 65 x 65 = 4225 tiles: 63 rows of tiles in one region, 2 in the other.
  EXPECT_EQ(checkRegions(bigFrame(520, 520, 8)), 2u);
  // 256 x 256 tiles: 16 regions of 16 rows.
  EXPECT_EQ(checkRegions(bigFrame(2048, 2048, 8)), 16u);
  // Ragged edges: the last tiles and regions are cut at the frame's border.
  EXPECT_EQ(checkRegions(bigFrame(1001, 777, 9)), 3u);
}

TEST(PlannerRegions, AFrameThatFitsOneAssemblyHasNoRegions) {
  const std::vector<PlannedTask> plan = planShot(bigFrame(512, 512, 8));  // 4096 tiles
  ASSERT_EQ(plan.size(), 4097u);
  EXPECT_EQ(plan.back().dependencies.size(), 4096u);
  for (size_t i = 0; i + 1 < plan.size(); ++i) EXPECT_EQ(plan[i].kind, TASK_RENDER_TILE);
}

// A frame taller than a filter window is denoised, upsampled, flowed, interpolated and
// composited by a task per window, whole rows that cover it once with the inputs of the
// frame's task, and the frame's task (the composite: the shot's output) joins them; what
// reads a frame's upsample, flow or interpolation reads the join.
TEST(Planner, AFrameTallerThanAFilterWindowIsFilteredWindowByWindow) {
  // Frames 10 to 19 of 64x64, keyframes every 4th (10, 14, 18, 19): 10 frames, each composited.
  ShotSpec spec = bigFrame(64, 64, 32);
  spec.set_pipeline(PIPELINE_DUI);
  spec.set_frame_start(10);
  spec.set_frame_end(19);
  spec.set_spp(16);
  spec.set_decompose("diffuse_direct=ED,residual");
  spec.set_keyframe_interval(4);
  spec.set_feature_spp(2);
  spec.set_filter_window_rows(kMinFilterWindowRows);  // 64 rows: four windows of 16
  const auto plan = planShot(spec);
  const auto kindsOf = [&](const std::vector<size_t>& dependencies) {
    std::multiset<TaskKind> kinds;
    for (const size_t d : dependencies) kinds.insert(plan[d].kind);
    return kinds;
  };
  for (const auto& [kind, frames] :
       {std::pair{TASK_COMPOSITE, 10}, std::pair{TASK_DENOISE, 4}, std::pair{TASK_UPSAMPLE, 4},
        std::pair{TASK_INTERPOLATE, 6}, std::pair{TASK_FLOW, 4}}) {  // flows: 2 pairs of keyframes, 2 components
    EXPECT_EQ(std::count_if(plan.begin(), plan.end(), [&](const PlannedTask& task) { return task.kind == kind; }),
              frames * 5);
    int joins = 0;
    for (const PlannedTask& task : plan) {
      if (task.kind != kind || task.params.has_window()) continue;
      ++joins;
      EXPECT_EQ(task.output, kind == TASK_COMPOSITE);
      ASSERT_EQ(task.dependencies.size(), 4u);
      std::vector<int> rows(64, 0);
      for (const size_t d : task.dependencies) {
        const PlannedTask& window = plan[d];
        ASSERT_EQ(window.kind, kind);
        EXPECT_FALSE(window.output);
        EXPECT_EQ(window.params.frame(), task.params.frame());
        EXPECT_EQ(window.params.window().x0(), 0);
        EXPECT_EQ(window.params.window().x1(), 64);
        EXPECT_EQ(window.params.window().y1() - window.params.window().y0(), 16);
        for (int y = window.params.window().y0(); y < window.params.window().y1(); ++y) ++rows[static_cast<size_t>(y)];
        if (kind == TASK_DENOISE) {  // the renders of the keyframe and its neighbours, whole
          EXPECT_GE(window.dependencies.size(), 2u);
          for (const size_t d : window.dependencies) EXPECT_EQ(plan[d].kind, TASK_ASSEMBLE_FRAME);
          continue;
        }
        if (kind == TASK_UPSAMPLE) {
          EXPECT_EQ(kindsOf(window.dependencies), (std::multiset<TaskKind>{TASK_DENOISE, TASK_ASSEMBLE_FRAME}));
          for (const size_t d : window.dependencies) EXPECT_FALSE(plan[d].params.has_window()) << "the joined denoise";
          continue;
        }
        if (kind == TASK_INTERPOLATE) {  // both keyframes' joined upsamples, the pair's flows, its features
          EXPECT_EQ(kindsOf(window.dependencies), (std::multiset<TaskKind>{TASK_UPSAMPLE, TASK_UPSAMPLE, TASK_FLOW,
                                                                           TASK_FLOW, TASK_ASSEMBLE_FRAME}));
          EXPECT_EQ(window.params.keyframe_before(), task.params.keyframe_before());
          EXPECT_EQ(window.params.keyframe_after(), task.params.keyframe_after());
          for (const size_t d : window.dependencies) EXPECT_FALSE(plan[d].params.has_window());
          continue;
        }
        if (kind == TASK_FLOW) {  // both keyframes' joined upsamples
          EXPECT_EQ(kindsOf(window.dependencies), (std::multiset<TaskKind>{TASK_UPSAMPLE, TASK_UPSAMPLE}));
          EXPECT_EQ(window.params.component(), task.params.component());
          EXPECT_EQ(window.params.keyframe_after(), task.params.keyframe_after());
          for (const size_t d : window.dependencies) EXPECT_FALSE(plan[d].params.has_window()) << "the joined upsample";
          continue;
        }
        ASSERT_EQ(window.dependencies.size(), 1u);  // the stage output; re-render tiles join later
        const PlannedTask& stage = plan[window.dependencies[0]];
        EXPECT_TRUE(stage.kind == TASK_UPSAMPLE || stage.kind == TASK_INTERPOLATE);
        EXPECT_FALSE(stage.params.has_window()) << "a composite reads its frame's joined upsample";
      }
      EXPECT_EQ(rows, std::vector<int>(64, 1)) << "frame " << task.params.frame();
    }
    EXPECT_EQ(joins, frames);
  }
  // d: the denoise writes the shot's frame, so its join is the shot's output.
  spec.set_pipeline(PIPELINE_D);
  size_t denoiseWindows = 0;
  for (const PlannedTask& task : planShot(spec)) {
    if (task.kind != TASK_DENOISE) continue;
    EXPECT_EQ(task.output, !task.params.has_window());
    denoiseWindows += task.params.has_window();
  }
  EXPECT_EQ(denoiseWindows, 10u * 4u);
  for (const int refused : {-1, kMinFilterWindowRows - 1}) {
    spec.set_filter_window_rows(refused);
    EXPECT_THROW(planShot(spec), PlanError) << refused;
  }
}

}  // namespace
}  // namespace pathfarm::farm
