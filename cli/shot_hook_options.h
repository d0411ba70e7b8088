#pragma once
// --on-done and --on-failed of `pathfarm local` and `pathfarm watch` (client/shot_hooks.h).
#include <CLI/CLI.hpp>

#include <string>

#include "client/shot_hooks.h"
#include "pathfarm/shot.pb.h"

namespace pathfarm {

inline void addShotHookOptions(CLI::App* command, farm::ShotHooks& hooks) {
  command->add_option("--on-done", hooks.onDone,
                      "shell command run when the shot is done (PATHFARM_SHOT_ID, _NAME, _STATE and _OUTPUT set)");
  command->add_option("--on-failed", hooks.onFailed, "shell command run when the shot fails or is cancelled (the same)");
}

inline farm::ShotOutcome outcomeOf(const farm::ShotSpec& spec, const farm::ShotSummary& summary,
                                   const std::string& output) {
  return {summary.id(), spec.name(), summary.state() == farm::SHOT_DONE, farm::ShotState_Name(summary.state()),
          output};
}

}  // namespace pathfarm
