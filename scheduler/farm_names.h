#pragma once
// The names people read for the farm's enums, in /metrics labels and the dashboard:
// "render_tile", "done", "running" rather than TASK_RENDER_TILE or a number.
#include <optional>
#include <string>

namespace pathfarm::farm {

// An enum value's protobuf name without its prefix, in lower case: "TASK_RENDER_TILE" with
// prefix "TASK_" is "render_tile".
std::string lowerWithout(const std::string& name, const std::string& prefix);
// The tasks and attempts tables' state numbers (scheduler/schema.h); "unknown" otherwise.
std::string taskStateName(int state);
std::string attemptStateName(int state);
// "ready" -> TaskState::Ready; nullopt for an unknown name.
std::optional<int> taskStateByName(const std::string& name);

}  // namespace pathfarm::farm
