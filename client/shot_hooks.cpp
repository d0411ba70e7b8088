#include "client/shot_hooks.h"

#include <spdlog/spdlog.h>

#include "client/child_process.h"

namespace pathfarm::farm {

std::optional<int> runShotHook(const ShotHooks& hooks, const ShotOutcome& outcome, std::chrono::milliseconds limit) {
  const std::string& command = outcome.done ? hooks.onDone : hooks.onFailed;
  if (command.empty()) return std::nullopt;
  const char* which = outcome.done ? "--on-done" : "--on-failed";
  spdlog::info("shot {} {}: running {}", outcome.id, outcome.state, which);
  ChildProcess hook({"/bin/sh", "-c", command}, "",
                    {"PATHFARM_SHOT_ID=" + std::to_string(outcome.id), "PATHFARM_SHOT_NAME=" + outcome.name,
                     "PATHFARM_SHOT_STATE=" + outcome.state, "PATHFARM_SHOT_OUTPUT=" + outcome.output});
  std::optional<int> status = hook.wait(limit);
  if (!status) {
    status = hook.stop();
    spdlog::warn("{} ran longer than {} s and was stopped", which,
                 std::chrono::duration_cast<std::chrono::seconds>(limit).count());
  } else if (*status != 0) {
    spdlog::warn("{} exited with status {}", which, *status);
  }
  return status;
}

}  // namespace pathfarm::farm
