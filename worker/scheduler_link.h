#pragma once
// A worker's calls to the scheduler: the WorkerService stub with the access token and a
// deadline on every call, and chunk transfer in bounded, verified parts.
#include <memory>
#include <string>

#include "pathfarm/worker_service.grpc.pb.h"

namespace pathfarm::farm {

class SchedulerLink {
 public:
  SchedulerLink(const std::string& address, std::string token);

  grpc::Status registerWorker(const std::string& name, int slots, RegisterReply& reply);
  grpc::Status lease(int64_t workerId, double waitSeconds, LeaseReply& reply);
  grpc::Status heartbeat(int64_t attemptId, double progress, HeartbeatReply& reply);
  grpc::Status complete(int64_t attemptId, const ChunkRef& output, ReportReply& reply);
  grpc::Status fail(int64_t attemptId, const std::string& reason, ReportReply& reply);
  grpc::Status putChunk(const std::string& bytes, ChunkRef& stored);
  grpc::Status getChunk(const std::string& sha256, std::string& bytes);

 private:
  std::unique_ptr<grpc::ClientContext> context(double seconds) const;
  std::unique_ptr<WorkerService::Stub> stub_;
  std::string token_;
};

}  // namespace pathfarm::farm
