#pragma once
// The scheduler's two gRPC services over one FarmState and one chunk store.
#include "pathfarm/client_service.grpc.pb.h"
#include "pathfarm/worker_service.grpc.pb.h"
#include "proto/wire/chunk_store.h"
#include "scheduler/farm_clock.h"
#include "scheduler/farm_signal.h"
#include "scheduler/farm_state.h"
#include "scheduler/worker_sessions.h"

namespace pathfarm::farm {

struct SchedulerContext {
  FarmState& state;
  ChunkStore& store;
  FarmSignal& signal;
  std::string token;  // empty: no access control
  ShotLimits limits;
};

class WorkerServiceImpl final : public WorkerService::Service {
 public:
  explicit WorkerServiceImpl(SchedulerContext context) : c_(context), sessions_(context.state) {}

  grpc::Status Register(grpc::ServerContext*, const RegisterRequest*, RegisterReply*) override;
  grpc::Status LeaseTask(grpc::ServerContext*, const LeaseRequest*, LeaseReply*) override;
  grpc::Status Heartbeat(grpc::ServerContext*, const HeartbeatRequest*, HeartbeatReply*) override;
  grpc::Status LeaseInputs(grpc::ServerContext*, const LeaseInputsRequest*,
                           grpc::ServerWriter<LeaseInputsPart>*) override;
  grpc::Status ReportFollowUps(grpc::ServerContext*, const FollowUpsRequest*, ReportReply*) override;
  grpc::Status CompleteTask(grpc::ServerContext*, const CompleteRequest*, ReportReply*) override;
  grpc::Status FailTask(grpc::ServerContext*, const FailRequest*, ReportReply*) override;
  grpc::Status PutChunk(grpc::ServerContext*, grpc::ServerReader<ChunkPart>*, PutChunkReply*) override;
  grpc::Status GetChunk(grpc::ServerContext*, const GetChunkRequest*, grpc::ServerWriter<ChunkPart>*) override;

 private:
  // Runs `body` with the calling worker's id, or refuses a call without a valid session.
  template <class Body>
  grpc::Status asWorker(grpc::ServerContext* context, Body&& body);
  // Refuses a report on an attempt leased to another worker.
  grpc::Status checkAttemptOwner(int64_t attemptId, int64_t workerId);
  SchedulerContext c_;
  WorkerSessions sessions_;
};

class ClientServiceImpl final : public ClientService::Service {
 public:
  explicit ClientServiceImpl(SchedulerContext context) : c_(context) {}

  grpc::Status MissingInputs(grpc::ServerContext*, const MissingInputsRequest*, MissingInputsReply*) override;
  grpc::Status PutInput(grpc::ServerContext*, grpc::ServerReader<ChunkPart>*, PutInputReply*) override;
  grpc::Status Submit(grpc::ServerContext*, const SubmitRequest*, SubmitReply*) override;
  grpc::Status ListShots(grpc::ServerContext*, const ListShotsRequest*, ListShotsReply*) override;
  grpc::Status GetShot(grpc::ServerContext*, const ShotRequest*, ShotReply*) override;
  grpc::Status GetReport(grpc::ServerContext*, const ShotRequest*, ShotReport*) override;
  grpc::Status WatchShot(grpc::ServerContext*, const ShotRequest*, grpc::ServerWriter<ShotSummary>*) override;
  grpc::Status CancelShot(grpc::ServerContext*, const ShotRequest*, ControlReply*) override;
  grpc::Status PauseShot(grpc::ServerContext*, const ShotRequest*, ControlReply*) override;
  grpc::Status ResumeShot(grpc::ServerContext*, const ShotRequest*, ControlReply*) override;
  grpc::Status RetryShot(grpc::ServerContext*, const ShotRequest*, ControlReply*) override;
  grpc::Status FetchOutputs(grpc::ServerContext*, const ShotRequest*, grpc::ServerWriter<OutputPart>*) override;
  grpc::Status ListWorkers(grpc::ServerContext*, const ListWorkersRequest*, ListWorkersReply*) override;
  grpc::Status SetPriority(grpc::ServerContext*, const PriorityRequest*, ControlReply*) override;
  grpc::Status Requeue(grpc::ServerContext*, const RequeueRequest*, ControlReply*) override;
  grpc::Status ListBlocklist(grpc::ServerContext*, const BlocklistRequest*, BlocklistReply*) override;
  grpc::Status ClearBlocklist(grpc::ServerContext*, const BlocklistRequest*, BlocklistReply*) override;

 private:
  // Why the shot's uploaded scene files cannot be used, or "" (client_service_inputs.cpp).
  std::string inputProblem(const ShotSpec& spec) const;
  template <class Change>
  grpc::Status controlShot(grpc::ServerContext* context, const ShotRequest* request, ControlReply* reply,
                           Change change);
  SchedulerContext c_;
};

}  // namespace pathfarm::farm
