#pragma once
// Turns a shot into its task graph. Pipeline "pt": every frame split into tiles, and an
// assemble task per frame that depends on that frame's tiles and joins them into the
// frame's EXR (a worker does the joining, so the scheduler never decodes images).
// Pipeline "noop": independent tasks that do nothing, for measuring the farm itself.
#include <stdexcept>
#include <vector>

#include "pathfarm/shot.pb.h"

namespace pathfarm::farm {

struct PlannedTask {
  TaskKind kind;
  TaskParams params;
  std::vector<size_t> dependencies;  // indices of earlier tasks in the plan
};

class PlanError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// Throws PlanError for a spec the farm cannot run (unknown pipeline, empty frame range...).
std::vector<PlannedTask> planShot(const ShotSpec& spec);

}  // namespace pathfarm::farm
