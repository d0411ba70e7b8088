#include "scheduler/service_chunks.h"

#include "proto/wire/chunk_store.h"
#include "proto/wire/chunk_transfer.h"
#include "proto/wire/connection.h"
#include "scheduler/output_check.h"

namespace pathfarm::farm {

ChunkRef storeReceivedChunk(grpc::ServerReader<ChunkPart>& reader, const SchedulerContext& c) {
  const ChunkRef stored = receiveChunkIntoStore(reader, c.store, kMaxChunkBytes);
  c.state.recordChunk(stored, farmClockSeconds());
  return stored;
}

grpc::Status lostChunk(const SchedulerContext& c, const std::string& sha256) {
  const int requeued = c.state.requeueProducersOf(sha256, farmClockSeconds());
  if (requeued == 0) return {grpc::StatusCode::NOT_FOUND, "no chunk " + sha256};
  c.signal.notify();
  return {grpc::StatusCode::NOT_FOUND, "chunk " + sha256 + " was missing or damaged: the " + std::to_string(requeued) +
                                           " task(s) that made it run again"};
}

std::string refusalOfCompletion(const SchedulerContext& c, const CompleteRequest& request) {
  const auto task = c.state.runningAttemptTask(request.attempt_id());
  if (!task || task->kind == TASK_NOOP) return {};
  const std::string& sha256 = request.output().sha256();
  if (!isSha256Hex(sha256) || !c.store.verifiedSize(sha256)) return {};  // the completion refuses a missing output
  return refusalOfOutput(c.store.pathOf(sha256), task->kind, task->params, task->spec);
}

}  // namespace pathfarm::farm
