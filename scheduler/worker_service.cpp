#include <algorithm>
#include <chrono>

#include "proto/wire/chunk_transfer.h"
#include "scheduler/received_chunk.h"
#include "scheduler/service_guard.h"

namespace pathfarm::farm {

grpc::Status WorkerServiceImpl::Register(grpc::ServerContext* context, const RegisterRequest* request,
                                         RegisterReply* reply) {
  return guarded(c_, context, [&] {
    const int slots = std::max(1, request->slots());
    for (const std::string& tag : request->tags())
      if (!isValidTag(tag))
        return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                            "tag \"" + tag + "\" is not letters, digits, '-', '_' or '.'");
    reply->set_worker_id(c_.state.registerWorker(request->name(), slots, wallClockSeconds(),
                                                 {request->tags().begin(), request->tags().end()}));
    // Three heartbeats fit in a lease: one lost message does not lose the lease.
    reply->set_heartbeat_seconds(c_.state.settings().leaseSeconds / 3);
    return grpc::Status::OK;
  });
}

grpc::Status WorkerServiceImpl::LeaseTask(grpc::ServerContext* context, const LeaseRequest* request,
                                          LeaseReply* reply) {
  return guarded(c_, context, [&] {
    if (!c_.state.workerExists(request->worker_id()))
      return grpc::Status(grpc::StatusCode::NOT_FOUND, "unknown worker: register again");
    // Long-poll: try, then sleep until the farm changes or the wait is over.
    const auto deadline = std::chrono::steady_clock::now() +
                          std::chrono::milliseconds(static_cast<int64_t>(std::clamp(request->wait_seconds(), 0.0, 60.0) * 1000));
    uint64_t seen = c_.signal.generation();
    for (;;) {
      if (auto lease = c_.state.lease(request->worker_id(), wallClockSeconds())) {
        reply->set_has_task(true);
        *reply->mutable_lease() = std::move(*lease);
        return grpc::Status::OK;
      }
      const auto now = std::chrono::steady_clock::now();
      if (now >= deadline || context->IsCancelled()) return grpc::Status::OK;
      // Retry backoff ends silently, so never sleep long without looking again.
      const auto wait = std::min<std::chrono::milliseconds>(
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline - now), std::chrono::milliseconds(250));
      seen = c_.signal.waitFor(seen, wait);
    }
  });
}

grpc::Status WorkerServiceImpl::Heartbeat(grpc::ServerContext* context, const HeartbeatRequest* request,
                                          HeartbeatReply* reply) {
  return guarded(c_, context, [&] {
    *reply = c_.state.heartbeat(request->attempt_id(), request->progress(), wallClockSeconds());
    return grpc::Status::OK;
  });
}

grpc::Status WorkerServiceImpl::CompleteTask(grpc::ServerContext* context, const CompleteRequest* request,
                                             ReportReply* reply) {
  return guarded(c_, context, [&] {
    *reply = c_.state.complete(*request, wallClockSeconds());
    if (reply->accepted()) c_.signal.notify();
    return grpc::Status::OK;
  });
}

grpc::Status WorkerServiceImpl::FailTask(grpc::ServerContext* context, const FailRequest* request,
                                         ReportReply* reply) {
  return guarded(c_, context, [&] {
    *reply = c_.state.fail(request->attempt_id(), request->reason(), wallClockSeconds());
    if (reply->accepted()) c_.signal.notify();
    return grpc::Status::OK;
  });
}

grpc::Status WorkerServiceImpl::PutChunk(grpc::ServerContext* context, grpc::ServerReader<ChunkPart>* reader,
                                         PutChunkReply* reply) {
  return guarded(c_, context, [&] {
    *reply->mutable_ref() = storeReceivedChunk(*reader, c_);
    return grpc::Status::OK;
  });
}

grpc::Status WorkerServiceImpl::GetChunk(grpc::ServerContext* context, const GetChunkRequest* request,
                                         grpc::ServerWriter<ChunkPart>* writer) {
  return guarded(c_, context, [&] {
    const auto bytes = c_.store.get(request->sha256());
    if (!bytes) return grpc::Status(grpc::StatusCode::NOT_FOUND, "no chunk " + request->sha256());
    ChunkRef ref;
    ref.set_sha256(request->sha256());
    ref.set_size(static_cast<int64_t>(bytes->size()));
    if (!sendChunk(*writer, ref, *bytes)) return grpc::Status(grpc::StatusCode::CANCELLED, "the reader went away");
    return grpc::Status::OK;
  });
}

}  // namespace pathfarm::farm
