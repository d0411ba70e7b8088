#pragma once
// Chunks moving through either service. One streamed in by a worker (a task's output) or
// a client (a scene file) is verified against its announced digest, then on disk
// (fsynced, renamed) before the row that names it commits.
#include "scheduler/scheduler_services.h"

namespace pathfarm::farm {

ChunkRef storeReceivedChunk(grpc::ServerReader<ChunkPart>& reader, const SchedulerContext& c);

// A chunk the store no longer has: the tasks that made it run again (FarmState::
// requeueProducersOf), and the status says so.
grpc::Status lostChunk(const SchedulerContext& c, const std::string& sha256);

// Why the output a completion names is refused (scheduler/output_check.h); empty when it
// is sound, and when the attempt is not running or its chunk not stored (FarmState then
// refuses the completion itself).
std::string refusalOfCompletion(const SchedulerContext& c, const CompleteRequest& request);

}  // namespace pathfarm::farm
