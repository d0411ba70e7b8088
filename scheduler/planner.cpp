#include "scheduler/planner.h"

#include <algorithm>
#include <string>

namespace pathfarm::farm {
namespace {

void checkRenderSpec(const ShotSpec& spec) {
  if (spec.frame_end() < spec.frame_start() || spec.frame_start() < 0)
    throw PlanError("frames: the range must satisfy 0 <= start <= end");
  if (spec.width() < 1 || spec.height() < 1 || spec.width() > 16384 || spec.height() > 16384)
    throw PlanError("resolution: width and height must be 1 to 16384");
  if (spec.spp() < 1) throw PlanError("spp: must be at least 1");
  if (spec.tile() < 8) throw PlanError("tile: must be at least 8 pixels");
}

void planPathTracing(const ShotSpec& spec, std::vector<PlannedTask>& plan) {
  checkRenderSpec(spec);
  const int tile = spec.tile();
  for (int64_t frame = spec.frame_start(); frame <= spec.frame_end(); ++frame) {
    PlannedTask assemble{TASK_ASSEMBLE_FRAME, {}, {}};
    assemble.params.set_frame(frame);
    for (int y = 0; y < spec.height(); y += tile) {
      for (int x = 0; x < spec.width(); x += tile) {
        PlannedTask render{TASK_RENDER_TILE, {}, {}};
        render.params.set_frame(frame);
        PixelWindow* window = render.params.mutable_window();
        window->set_x0(x);
        window->set_y0(y);
        window->set_x1(std::min(x + tile, spec.width()));
        window->set_y1(std::min(y + tile, spec.height()));
        assemble.dependencies.push_back(plan.size());
        plan.push_back(std::move(render));
      }
    }
    plan.push_back(std::move(assemble));
  }
}

}  // namespace

std::vector<PlannedTask> planShot(const ShotSpec& spec) {
  std::vector<PlannedTask> plan;
  if (spec.pipeline() == "pt") {
    planPathTracing(spec, plan);
  } else if (spec.pipeline() == "noop") {
    if (spec.noop_tasks() < 1) throw PlanError("noop_tasks: must be at least 1");
    plan.assign(static_cast<size_t>(spec.noop_tasks()), PlannedTask{TASK_NOOP, {}, {}});
  } else {
    throw PlanError("pipeline \"" + spec.pipeline() + "\" is not available (this farm runs: pt, noop)");
  }
  return plan;
}

}  // namespace pathfarm::farm
