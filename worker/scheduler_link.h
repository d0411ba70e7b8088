#pragma once
// A worker's calls to the scheduler: the WorkerService stub with the access token and a
// deadline on every call, and chunk transfer in bounded, verified parts.
#include <filesystem>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "pathfarm/worker_service.grpc.pb.h"
#include "proto/wire/chunk_store.h"
#include "proto/wire/connection.h"
#include "proto/wire/tls.h"
#include "worker/backoff.h"

namespace pathfarm::farm {

class SchedulerLink {
 public:
  SchedulerLink(const std::string& address, std::string token, const ClientTls& tls = {});

  // On success every later call carries the session the reply hands out.
  grpc::Status registerWorker(const std::string& name, int slots, const std::vector<std::string>& tags,
                              RegisterReply& reply);
  // After a call was refused for its session `refused` (a scheduler on a fresh database
  // forgot it): registers again, unless another slot already did since. So one worker
  // process holds one registration, and every slot the session that goes with it.
  grpc::Status registerAgain(const WorkerSession& refused, const std::string& name, int slots,
                             const std::vector<std::string>& tags);
  // A long-poll for a task, for this worker's session (which it returns in `used`);
  // returns CANCELLED at once after stopLeasing().
  grpc::Status lease(double waitSeconds, LeaseReply& reply, WorkerSession& used);
  // Ends the long-polls under way and refuses new ones: a stopping worker need not wait
  // for them to time out.
  void stopLeasing();
  grpc::Status heartbeat(int64_t attemptId, double progress, HeartbeatReply& reply);
  // The inputs of a lease leased without them (Lease::inputs_streamed), appended to it.
  grpc::Status leaseInputs(Lease& lease);
  grpc::Status reportFollowUps(const FollowUpsRequest& request, ReportReply& reply);
  grpc::Status complete(const CompleteRequest& request, ReportReply& reply);
  grpc::Status fail(const FailRequest& request, ReportReply& reply);
  grpc::Status putChunk(const std::string& bytes, ChunkRef& stored);
  // The bytes of `file`, read in parts (an output too large to hold); a file that cannot
  // be read is an INTERNAL error.
  grpc::Status putChunkFile(const std::filesystem::path& file, ChunkRef& stored);
  grpc::Status getChunk(const std::string& sha256, std::string& bytes);
  // The chunk streamed into `store` as it arrives, never held whole (an input too large to
  // hold); DATA_LOSS when its bytes do not match its digest.
  grpc::Status getChunkInto(const std::string& sha256, ChunkStore& store);

  // Waits `delay` between attempts, or less: while the connection is down, until it is up
  // again. A worker with no call in flight otherwise learns that the scheduler is back
  // only from gRPC's backup poller, every 5 s, after a connection backoff that grows to
  // minutes: a scheduler restart of under a second kept workers away for 10 to 20 s
  // (bench/netns_farm.sh, scheduler-restart).
  void pause(std::chrono::milliseconds delay);
  // A Backoff whose waits are pause()s.
  Backoff backoff();

 private:
  // A call's context with the token and the current session (copied to `used` if given).
  std::unique_ptr<grpc::ClientContext> context(double seconds, WorkerSession* used = nullptr) const;
  // A PutChunk call whose parts `send` writes to the stream it is handed.
  template <class Send>
  grpc::Status put(ChunkRef& stored, Send send);
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<WorkerService::Stub> stub_;
  std::string token_;
  mutable std::mutex sessionMutex_;
  WorkerSession session_;
  std::mutex registerMutex_;  // one re-registration at a time
  std::mutex mutex_;
  bool leasingStopped_ = false;
  std::set<grpc::ClientContext*> pendingLeases_;
};

}  // namespace pathfarm::farm
