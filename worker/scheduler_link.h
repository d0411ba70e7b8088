#pragma once
// A worker's calls to the scheduler: the WorkerService stub with the access token and a
// deadline on every call, and chunk transfer in bounded, verified parts.
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "pathfarm/worker_service.grpc.pb.h"
#include "proto/wire/connection.h"
#include "proto/wire/tls.h"

namespace pathfarm::farm {

class SchedulerLink {
 public:
  SchedulerLink(const std::string& address, std::string token, const ClientTls& tls = {});

  // On success every later call carries the session the reply hands out.
  grpc::Status registerWorker(const std::string& name, int slots, const std::vector<std::string>& tags,
                              RegisterReply& reply);
  // A long-poll for a task; returns CANCELLED at once after stopLeasing().
  grpc::Status lease(int64_t workerId, double waitSeconds, LeaseReply& reply);
  // Ends the long-polls under way and refuses new ones: a stopping worker need not wait
  // for them to time out.
  void stopLeasing();
  grpc::Status heartbeat(int64_t attemptId, double progress, HeartbeatReply& reply);
  grpc::Status complete(const CompleteRequest& request, ReportReply& reply);
  grpc::Status fail(int64_t attemptId, const std::string& reason, ReportReply& reply);
  grpc::Status putChunk(const std::string& bytes, ChunkRef& stored);
  grpc::Status getChunk(const std::string& sha256, std::string& bytes);

 private:
  std::unique_ptr<grpc::ClientContext> context(double seconds) const;
  std::unique_ptr<WorkerService::Stub> stub_;
  std::string token_;
  mutable std::mutex sessionMutex_;
  WorkerSession session_;
  std::mutex mutex_;
  bool leasingStopped_ = false;
  std::set<grpc::ClientContext*> pendingLeases_;
};

}  // namespace pathfarm::farm
