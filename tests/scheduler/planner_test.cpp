#include <gtest/gtest.h>

#include <set>

#include "scheduler/planner.h"

namespace pathfarm::farm {
namespace {

ShotSpec renderSpec() {
  ShotSpec spec;
  spec.set_pipeline("pt");
  spec.set_frame_start(3);
  spec.set_frame_end(4);
  spec.set_width(100);
  spec.set_height(70);
  spec.set_spp(4);
  spec.set_tile(32);
  return spec;
}

TEST(Planner, TilesCoverEachFrameOnceAndAssemblyWaitsForThem) {
  const auto plan = planShot(renderSpec());
  // 4 x 3 tiles per frame plus one assemble task, for 2 frames.
  ASSERT_EQ(plan.size(), 2u * (12 + 1));
  for (int64_t frame : {3, 4}) {
    std::vector<int> covered(100 * 70, 0);
    const PlannedTask* assemble = nullptr;
    for (size_t i = 0; i < plan.size(); ++i) {
      const PlannedTask& task = plan[i];
      if (task.params.frame() != frame) continue;
      if (task.kind == TASK_ASSEMBLE_FRAME) {
        assemble = &task;
        continue;
      }
      ASSERT_EQ(task.kind, TASK_RENDER_TILE);
      EXPECT_TRUE(task.dependencies.empty());
      const PixelWindow& w = task.params.window();
      for (int y = w.y0(); y < w.y1(); ++y)
        for (int x = w.x0(); x < w.x1(); ++x) ++covered[static_cast<size_t>(y * 100 + x)];
    }
    for (int c : covered) ASSERT_EQ(c, 1);
    ASSERT_NE(assemble, nullptr);
    std::set<size_t> deps(assemble->dependencies.begin(), assemble->dependencies.end());
    EXPECT_EQ(deps.size(), 12u);
    for (size_t d : deps) {
      EXPECT_EQ(plan[d].params.frame(), frame);
      EXPECT_LT(d, static_cast<size_t>(assemble - plan.data()));  // dependencies come first
    }
  }
}

TEST(Planner, RefusesWhatItCannotRun) {
  ShotSpec spec = renderSpec();
  spec.set_pipeline("dui");
  EXPECT_THROW(planShot(spec), PlanError);
  spec = renderSpec();
  spec.set_frame_end(2);
  EXPECT_THROW(planShot(spec), PlanError);
  spec = renderSpec();
  spec.set_tile(0);
  EXPECT_THROW(planShot(spec), PlanError);
  spec.set_pipeline("noop");
  spec.set_noop_tasks(5);
  EXPECT_EQ(planShot(spec).size(), 5u);
}

}  // namespace
}  // namespace pathfarm::farm
