#pragma once
// The dashboard's JSON: the farm's records as the page reads them. Enum values become
// their lower-case names ("running", "render_tile"), times stay seconds since the epoch.
#include <nlohmann/json.hpp>

#include "scheduler/farm_state.h"

namespace pathfarm::farm {

nlohmann::json shotJson(const ShotSummary& summary);
// A shot's page: its summary, the spec's main settings, its last events, the frames it
// has produced (with the chunk digests that name their thumbnails) and its blocklist.
nlohmann::json shotPageJson(const ShotReply& shot, const std::vector<std::pair<int64_t, ChunkRef>>& frames,
                            const std::vector<BlocklistEntry>& blocklist);
// A page of a shot's tasks, each with its attempts and the shot's events that name it.
nlohmann::json tasksJson(const FarmState::TaskPage& page, const std::vector<ShotEvent>& events, double now);
// Workers with their state (busy, idle or gone, as /metrics counts them), their running
// tasks, and the blocklist of every shot.
nlohmann::json workersJson(const std::vector<WorkerInfo>& workers, const std::vector<FarmState::RunningTask>& running,
                           const std::vector<BlocklistEntry>& blocklist, double leaseSeconds, double now);

nlohmann::json blocklistJson(const std::vector<BlocklistEntry>& entries);

}  // namespace pathfarm::farm
