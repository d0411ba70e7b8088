#pragma once
// Tasks as the farm's state records them, for tests of what is built from them (reports).
#include "scheduler/farm_state.h"

namespace pathfarm::farm {

inline TaskRecord taskRecord(TaskKind kind, TaskRole role, int64_t frame, double coreSeconds, bool done = true) {
  TaskRecord task;
  task.kind = kind;
  task.params.set_role(role);
  task.params.set_frame(frame);
  task.coreSeconds = coreSeconds;
  task.done = done;
  return task;
}

}  // namespace pathfarm::farm
