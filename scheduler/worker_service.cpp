#include <algorithm>
#include <chrono>

#include "proto/wire/chunk_transfer.h"
#include "scheduler/quoted_text.h"
#include "scheduler/service_chunks.h"
#include "scheduler/service_guard.h"

namespace pathfarm::farm {
namespace {

constexpr const char* kNoLongerLeased = "the attempt is no longer leased (expired, revoked or superseded)";

}  // namespace

template <class Body>
grpc::Status WorkerServiceImpl::asWorker(grpc::ServerContext* context, Body&& body) {
  return guarded(c_, context, [&] {
    const std::optional<int64_t> worker = sessions_.workerOf(*context);
    if (!worker)
      return grpc::Status(grpc::StatusCode::UNAUTHENTICATED, "no valid worker session: register again");
    return body(*worker);
  });
}

grpc::Status WorkerServiceImpl::checkAttemptOwner(int64_t attemptId, int64_t workerId) {
  const std::optional<int64_t> owner = c_.state.attemptWorker(attemptId);
  if (owner && *owner != workerId)
    return {grpc::StatusCode::PERMISSION_DENIED,
            "attempt " + std::to_string(attemptId) + " was leased to another worker"};
  return grpc::Status::OK;  // an unknown attempt is refused as stale by FarmState
}

grpc::Status WorkerServiceImpl::Register(grpc::ServerContext* context, const RegisterRequest* request,
                                         RegisterReply* reply) {
  return guarded(c_, context, [&] {
    const int slots = std::max(1, request->slots());
    for (const std::string& tag : request->tags())
      if (!isValidTag(tag))
        return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                            "tag " + quotedInput(tag) + " is not letters, digits, '-', '_' or '.'");
    const NewSession session = WorkerSessions::make();
    reply->set_worker_id(c_.state.registerWorker(request->name(), slots, farmClockSeconds(),
                                                 {request->tags().begin(), request->tags().end()}, session.hash));
    reply->set_session_key(session.key);
    sessions_.remember(reply->worker_id(), session.hash);
    // Three heartbeats fit in a lease: one lost message does not lose the lease.
    reply->set_heartbeat_seconds(c_.state.settings().leaseSeconds / 3);
    return grpc::Status::OK;
  });
}

grpc::Status WorkerServiceImpl::LeaseTask(grpc::ServerContext* context, const LeaseRequest* request,
                                          LeaseReply* reply) {
  return asWorker(context, [&](int64_t worker) {
    if (request->worker_id() != worker)
      return grpc::Status(grpc::StatusCode::PERMISSION_DENIED, "a worker leases for itself only");
    // Long-poll: try, then sleep until the farm changes or the wait is over.
    const auto deadline = std::chrono::steady_clock::now() +
                          std::chrono::milliseconds(static_cast<int64_t>(std::clamp(request->wait_seconds(), 0.0, 60.0) * 1000));
    uint64_t seen = c_.signal.generation();
    for (;;) {
      // A worker that hung up (stopping) must not be handed a task it will never see: that
      // task would wait a whole lease period for the lease to expire.
      if (context->IsCancelled()) return grpc::Status::OK;
      if (auto lease = c_.state.lease(request->worker_id(), farmClockSeconds())) {
        reply->set_has_task(true);
        *reply->mutable_lease() = std::move(*lease);
        return grpc::Status::OK;
      }
      const auto now = std::chrono::steady_clock::now();
      if (now >= deadline) return grpc::Status::OK;
      // Retry backoff ends silently, so never sleep long without looking again.
      const auto wait = std::min<std::chrono::milliseconds>(
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline - now), std::chrono::milliseconds(250));
      seen = c_.signal.waitFor(seen, wait);
    }
  });
}

grpc::Status WorkerServiceImpl::Heartbeat(grpc::ServerContext* context, const HeartbeatRequest* request,
                                          HeartbeatReply* reply) {
  return asWorker(context, [&](int64_t worker) {
    if (grpc::Status owner = checkAttemptOwner(request->attempt_id(), worker); !owner.ok()) return owner;
    *reply = c_.state.heartbeat(request->attempt_id(), request->progress(), farmClockSeconds());
    return grpc::Status::OK;
  });
}

grpc::Status WorkerServiceImpl::LeaseInputs(grpc::ServerContext* context, const LeaseInputsRequest* request,
                                            grpc::ServerWriter<LeaseInputsPart>* writer) {
  return asWorker(context, [&](int64_t worker) {
    if (grpc::Status owner = checkAttemptOwner(request->attempt_id(), worker); !owner.ok()) return owner;
    // A part per transaction: the database is not held while a slow reader takes them.
    for (int64_t after = 0;;) {
      const auto part = c_.state.leaseInputs(request->attempt_id(), after);
      if (!part) return grpc::Status(grpc::StatusCode::FAILED_PRECONDITION, kNoLongerLeased);
      if (part->lastTaskId == 0) return grpc::Status::OK;
      if (!writer->Write(part->part)) return grpc::Status(grpc::StatusCode::CANCELLED, "the reader went away");
      after = part->lastTaskId;
    }
  });
}

grpc::Status WorkerServiceImpl::ReportFollowUps(grpc::ServerContext* context, const FollowUpsRequest* request,
                                                ReportReply* reply) {
  return asWorker(context, [&](int64_t worker) {
    if (grpc::Status owner = checkAttemptOwner(request->attempt_id(), worker); !owner.ok()) return owner;
    *reply = c_.state.stageFollowUps(request->attempt_id(), request->follow_ups());
    return grpc::Status::OK;
  });
}

grpc::Status WorkerServiceImpl::CompleteTask(grpc::ServerContext* context, const CompleteRequest* request,
                                             ReportReply* reply) {
  return asWorker(context, [&](int64_t worker) {
    if (grpc::Status owner = checkAttemptOwner(request->attempt_id(), worker); !owner.ok()) return owner;
    if (const std::string refusal = refusalOfCompletion(c_, *request); !refusal.empty()) {
      // The worker's doing: the task runs again, elsewhere if the worker keeps at it.
      const std::string reason = "its output was refused: " + refusal;
      c_.state.fail(request->attempt_id(), reason, farmClockSeconds(), request->log_tail(), FAILURE_WORKER_FAULT);
      reply->set_accepted(false);
      reply->set_reason(reason);
      c_.signal.notify();
      return grpc::Status::OK;
    }
    *reply = c_.state.complete(*request, farmClockSeconds());
    if (reply->accepted()) c_.signal.notify();
    return grpc::Status::OK;
  });
}

grpc::Status WorkerServiceImpl::FailTask(grpc::ServerContext* context, const FailRequest* request,
                                         ReportReply* reply) {
  return asWorker(context, [&](int64_t worker) {
    if (grpc::Status owner = checkAttemptOwner(request->attempt_id(), worker); !owner.ok()) return owner;
    *reply = c_.state.fail(request->attempt_id(), request->reason(), farmClockSeconds(), request->log_tail(),
                           request->failure_class());
    if (reply->accepted()) c_.signal.notify();
    return grpc::Status::OK;
  });
}

grpc::Status WorkerServiceImpl::PutChunk(grpc::ServerContext* context, grpc::ServerReader<ChunkPart>* reader,
                                         PutChunkReply* reply) {
  return asWorker(context, [&](int64_t) {
    *reply->mutable_ref() = storeReceivedChunk(*reader, c_);
    return grpc::Status::OK;
  });
}

grpc::Status WorkerServiceImpl::GetChunk(grpc::ServerContext* context, const GetChunkRequest* request,
                                         grpc::ServerWriter<ChunkPart>* writer) {
  return asWorker(context, [&](int64_t) {
    switch (sendStoredChunk(*writer, c_.store, request->sha256())) {
      case StoredSend::Absent:
        return lostChunk(c_, request->sha256());
      case StoredSend::ReaderGone:
        return grpc::Status(grpc::StatusCode::CANCELLED, "the reader went away");
      case StoredSend::Sent:
        break;
    }
    return grpc::Status::OK;
  });
}

}  // namespace pathfarm::farm
