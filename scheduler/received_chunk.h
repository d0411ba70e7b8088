#pragma once
// A chunk streamed in by a worker (a task's output) or a client (a scene file): verified
// against its announced digest, then on disk (fsynced, renamed) before the row that names
// it commits.
#include "proto/wire/chunk_transfer.h"
#include "proto/wire/connection.h"
#include "scheduler/scheduler_services.h"

namespace pathfarm::farm {

inline ChunkRef storeReceivedChunk(grpc::ServerReader<ChunkPart>& reader, const SchedulerContext& c) {
  ChunkRef announced;
  const std::string bytes = receiveChunk(reader, announced, kMaxChunkBytes);
  const ChunkRef stored = c.store.put(bytes, announced);
  c.state.recordChunk(stored, wallClockSeconds());
  return stored;
}

}  // namespace pathfarm::farm
