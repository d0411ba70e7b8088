#pragma once
// The options that bound how large a shot a scheduler takes, how its large tasks are
// leased and what its store keeps: `pathfarm scheduler` and the embedded farm of
// `pathfarm local` take the same.
#include <CLI/CLI.hpp>

#include <cstdint>

#include "scheduler/farm_state.h"
#include "scheduler/planner.h"

namespace pathfarm {

inline void addShotSizeOptions(CLI::App* command, farm::ShotLimits& limits, farm::FarmSettings& farm) {
  command->add_option("--lease-inputs", farm.inlineLeaseInputs,
                      "a lease names at most this many input chunks; a task with more streams them to its worker")
      ->check(CLI::Range(int64_t{0}, int64_t{1'000'000}))
      ->capture_default_str();
  command->add_option("--max-tasks-per-shot", limits.maxTasks, "a shot planning more tasks is refused")
      ->check(CLI::Range(int64_t{1}, int64_t{1'000'000'000}))
      ->capture_default_str();
  command->add_option("--max-frames-per-shot", limits.maxFrames, "a shot with more frames is refused")
      ->check(CLI::Range(int64_t{1}, int64_t{1'000'000'000}))
      ->capture_default_str();
  command->add_flag("--keep-intermediates", farm.keepIntermediates,
                    "keep every task's output chunk until retention (default: an intermediate chunk, such as a "
                    "render tile or a filtered keyframe, leaves the store once no task reads it)");
}

}  // namespace pathfarm
