#pragma once
// Turns a shot into its task graph (docs/farm.md, "Task graphs").
//   pt    every frame split into tiles, and an assemble task per frame that depends on
//         that frame's tiles and joins them into the frame's EXR (a worker does the joining,
//         so the scheduler never decodes images);
//   d, du, di, dui  the filtering pipelines (Zimmer et al. 2015): keyframes rendered (with
//         motion vectors reaching the neighbouring keyframes) and filtered, in-between
//         frames interpolated, a composite per frame; re-render tiles are added while the
//         shot runs (FarmState::complete). d re-renders nothing: its denoise task (role
//         output) writes the final frame, without a composite;
//   tgpt  temporal gradient-domain path tracing: a gradient render per frame, a screened
//         Poisson reconstruction per window of frames, a blend per frame;
//   pssmlt, mlt, tmlt  Metropolis light transport: per window of frames (one frame for mlt)
//         a seed-pool task, chain-batch tasks over ranges of chain blocks depending on it,
//         and per frame a merge task depending on all of them;
//   noop  independent tasks that do nothing, for measuring the farm itself.
// Every render pipeline adds the evaluation tasks the report needs: the baseline (plain pt
// at the shot's spp, baseline_repeats times from disjoint samples) and, with reference_spp, the reference of the evaluation frames and
// an evaluate task comparing every stage against it.
#include <stdexcept>
#include <vector>

#include "contract/pipeline.h"
#include "pathfarm/shot.pb.h"

namespace pathfarm::farm {

// The most inputs an assemble task reads: a lease naming them stays far below gRPC's
// message limit (about 100 bytes each against 8 MiB).
inline constexpr int64_t kMaxAssemblyInputs = 4096;

struct PlannedTask {
  TaskKind kind;
  TaskParams params;
  std::vector<size_t> dependencies;  // indices of earlier tasks in the plan
  bool output = false;               // one of the shot's frames
};

class PlanError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// Throws PlanError for a spec the farm cannot run (unknown pipeline, empty frame range...).
std::vector<PlannedTask> planShot(const ShotSpec& spec);

// A worker tag or a shot's required tag: 1 to 64 letters, digits, '-', '_' or '.'.
bool isValidTag(const std::string& tag);

// What one shot may ask of a scheduler, so that a mistyped frame range cannot plan
// billions of tasks or hold the database in one transaction for minutes.
struct ShotLimits {
  int64_t maxFrames = 1'000'000;
  double maxPixelFrames = 1e12;  // width x height x frames
  int64_t maxTasks = 1'000'000;
};
// A lower bound of planShot(spec).size(), counted without planning: pt and the filtering
// pipelines render every frame in tiles and assemble it.
int64_t plannedTasksAtLeast(const ShotSpec& spec);
// The plan of a spec within `limits`: the frames, pixels and plannedTasksAtLeast are
// checked before planning, the task count after; throws PlanError naming the limit and how
// to raise it.
std::vector<PlannedTask> planShotWithin(const ShotSpec& spec, const ShotLimits& limits);

}  // namespace pathfarm::farm
