#pragma once
// Commands run when a shot ends (`pathfarm local`, `pathfarm watch`): one when it is done,
// one when it failed or was cancelled. /bin/sh runs them with the shot in the environment:
// PATHFARM_SHOT_ID, PATHFARM_SHOT_NAME, PATHFARM_SHOT_STATE (SHOT_DONE, SHOT_FAILED,
// SHOT_CANCELLED) and PATHFARM_SHOT_OUTPUT (its frames' folder). A webhook is such a
// command, e.g. curl --data "$PATHFARM_SHOT_STATE" https://example/hook.
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

namespace pathfarm::farm {

struct ShotHooks {
  std::string onDone, onFailed;
};

struct ShotOutcome {
  int64_t id = 0;
  std::string name;
  bool done = false;
  std::string state;   // ShotState's name
  std::string output;  // the folder its frames are in
};

// Runs the command the outcome asks for, waiting at most `limit` (then stopping it), with
// its output on this process's. Returns its exit status (128 + signal when it was
// stopped), or nothing when no command applies. A command that fails is logged as a
// warning; it changes nothing else.
std::optional<int> runShotHook(const ShotHooks& hooks, const ShotOutcome& outcome,
                               std::chrono::milliseconds limit = std::chrono::minutes(10));

}  // namespace pathfarm::farm
