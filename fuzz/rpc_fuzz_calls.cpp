#include "fuzz/rpc_fuzz_calls.h"

#include <grpcpp/test/server_context_test_spouse.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "proto/wire/sha256.h"

namespace pathfarm::fuzz {
namespace {

enum Call : uint8_t {
  kRegister,
  kLeaseTask,
  kHeartbeat,
  kCompleteTask,
  kFailTask,
  kPutChunk,
  kGetChunk,
  kMissingInputs,
  kPutInput,
  kSubmit,
  kListShots,
  kGetShot,
  kGetReport,
  kWatchShot,
  kCancelShot,
  kPauseShot,
  kResumeShot,
  kRetryShot,
  kFetchOutputs,
  kListWorkers,
  kSetPriority,
  kRequeue,
  kListBlocklist,
  kClearBlocklist,
  kLeaseInputs,
  kReportFollowUps,
};
static_assert(kReportFollowUps + 1 == RpcCalls::kCalls);

constexpr uint8_t kOutsider = RpcCalls::kOutsider;

template <class Message>
Message parsed(std::string_view bytes) {
  Message message;
  if (!message.ParseFromArray(bytes.data(), static_cast<int>(bytes.size()))) message.Clear();
  return message;
}

// Splits [length, 2 bytes][part bytes]... into parts.
std::vector<farm::ChunkPart> chunkParts(std::string_view bytes) {
  std::vector<farm::ChunkPart> parts;
  while (bytes.size() >= 2) {
    const size_t length =
        std::min<size_t>(static_cast<uint8_t>(bytes[0]) | static_cast<uint8_t>(bytes[1]) << 8, bytes.size() - 2);
    parts.push_back(parsed<farm::ChunkPart>(bytes.substr(2, length)));
    bytes.remove_prefix(2 + length);
  }
  return parts;
}

// A refusal names its reason with a status a caller can act on; INTERNAL and UNKNOWN
// mean a handler met an exception nobody meant (service_guard.h), and are findings. With
// PATHFARM_FUZZ_VERBOSE set (to check what the seeds reach), every call's status.
void note(uint8_t op, const grpc::Status& status) {
  static const bool verbose = std::getenv("PATHFARM_FUZZ_VERBOSE") != nullptr;
  const bool unexpected =
      status.error_code() == grpc::StatusCode::INTERNAL || status.error_code() == grpc::StatusCode::UNKNOWN;
  if (verbose || unexpected)
    std::fprintf(stderr, "call %d%s: %d %s\n", (op & ~kOutsider) % RpcCalls::kCalls,
                 op & kOutsider ? " (outsider)" : "", static_cast<int>(status.error_code()),
                 status.error_message().c_str());
  if (unexpected) std::abort();
}

}  // namespace

RpcCalls::RpcCalls(farm::WorkerServiceImpl& workers, farm::ClientServiceImpl& clients,
                   std::function<std::shared_ptr<grpc::Channel>()> streamChannel)
    : workers_(workers), clients_(clients), streamChannel_(std::move(streamChannel)) {}

farm::WorkerService::Stub& RpcCalls::workerStub() {
  if (!workerStub_) workerStub_ = farm::WorkerService::NewStub(streamChannel_());
  return *workerStub_;
}

farm::ClientService::Stub& RpcCalls::clientStub() {
  if (!clientStub_) clientStub_ = farm::ClientService::NewStub(streamChannel_());
  return *clientStub_;
}

void RpcCalls::prepare(grpc::ClientContext& context, uint8_t op, bool worker) const {
  // In-process calls answer in microseconds; the deadline only stops a call that hangs,
  // which libFuzzer's -timeout then reports.
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(5));
  if (op & kOutsider) return;
  farm::attachToken(context, kFuzzToken);
  if (worker && session_.workerId != 0) farm::attachSession(context, session_);
}

grpc::Status RpcCalls::call(uint8_t op, bool worker, const std::function<grpc::Status(grpc::ServerContext*)>& handle) {
  grpc::ServerContext context;
  grpc::testing::ServerContextTestSpouse metadata(&context);
  if (!(op & kOutsider)) {
    metadata.AddClientMetadata(farm::kTokenHeader, kFuzzToken);
    if (worker && session_.workerId != 0)
      metadata.AddClientMetadata(farm::kSessionHeader, farm::sessionHeaderValue(session_));
  }
  const grpc::Status status = handle(&context);
  note(op, status);
  return status;
}

template <class Reply, class Open>
void RpcCalls::upload(uint8_t op, bool worker, Open open, std::string_view parts) {
  grpc::ClientContext context;
  prepare(context, op, worker);
  Reply reply;
  const auto writer = open(&context, &reply);
  for (const farm::ChunkPart& part : chunkParts(parts))
    if (!writer->Write(part)) break;
  writer->WritesDone();
  note(op, writer->Finish());
}

template <class Part, class Open>
void RpcCalls::download(uint8_t op, bool worker, Open open, std::chrono::milliseconds limit) {
  grpc::ClientContext context;
  prepare(context, op, worker);
  context.set_deadline(std::chrono::system_clock::now() + limit);
  const auto reader = open(&context);
  Part part;
  while (reader->Read(&part)) {
  }
  note(op, reader->Finish());
}

template <class Service, class Request, class Reply>
std::pair<grpc::Status, Reply> RpcCalls::unary(uint8_t op, bool worker, Service& service,
                                               Handler<Service, Request, Reply> handler, const Request& request) {
  Reply reply;
  const grpc::Status status =
      call(op, worker, [&](grpc::ServerContext* c) { return (service.*handler)(c, &request, &reply); });
  return {status, reply};
}

void RpcCalls::run(uint8_t op, std::string_view bytes) {
  using W = farm::WorkerServiceImpl;
  using C = farm::ClientServiceImpl;
  constexpr bool kWorker = true, kClient = false;
  constexpr std::chrono::milliseconds kStream{2000};
  // A shot or an attempt left 0 names the last one this input submitted or leased, which
  // the fuzzer could not guess from its bytes.
  const auto withShot = [&](auto request) {
    if (request.shot_id() == 0) request.set_shot_id(lastShot_);
    return request;
  };
  const auto withAttempt = [&](auto request) {
    if (request.attempt_id() == 0) request.set_attempt_id(lastAttempt_);
    return request;
  };
  const auto shotRequest = [&] { return withShot(parsed<farm::ShotRequest>(bytes)); };
  switch ((op & ~kOutsider) % kCalls) {
    case kRegister: {
      const auto [status, reply] = unary(op, kClient, workers_, &W::Register, parsed<farm::RegisterRequest>(bytes));
      if (status.ok()) session_ = {reply.worker_id(), reply.session_key()};
      break;
    }
    case kLeaseTask: {
      auto request = parsed<farm::LeaseRequest>(bytes);
      if (request.worker_id() == 0) request.set_worker_id(session_.workerId);
      request.set_wait_seconds(0);  // a long poll would only wait for the deadline
      const auto [status, reply] = unary(op, kWorker, workers_, &W::LeaseTask, request);
      if (status.ok() && reply.has_task()) lastAttempt_ = reply.lease().attempt_id();
      break;
    }
    case kHeartbeat:
      unary(op, kWorker, workers_, &W::Heartbeat, withAttempt(parsed<farm::HeartbeatRequest>(bytes)));
      break;
    case kCompleteTask:
      unary(op, kWorker, workers_, &W::CompleteTask, withAttempt(parsed<farm::CompleteRequest>(bytes)));
      break;
    case kFailTask:
      unary(op, kWorker, workers_, &W::FailTask, withAttempt(parsed<farm::FailRequest>(bytes)));
      break;
    case kPutChunk:
      upload<farm::PutChunkReply>(
          op, kWorker, [&](auto* c, auto* r) { return workerStub().PutChunk(c, r); }, bytes);
      break;
    case kGetChunk: {
      const auto request = parsed<farm::GetChunkRequest>(bytes);
      download<farm::ChunkPart>(
          op, kWorker, [&](auto* c) { return workerStub().GetChunk(c, request); }, kStream);
      break;
    }
    case kMissingInputs:
      unary(op, kClient, clients_, &C::MissingInputs, parsed<farm::MissingInputsRequest>(bytes));
      break;
    case kPutInput:
      upload<farm::PutInputReply>(
          op, kClient, [&](auto* c, auto* r) { return clientStub().PutInput(c, r); }, bytes);
      break;
    case kSubmit: {
      const auto [status, reply] = unary(op, kClient, clients_, &C::Submit, parsed<farm::SubmitRequest>(bytes));
      if (status.ok()) lastShot_ = reply.shot_id();
      break;
    }
    case kListShots:
      unary(op, kClient, clients_, &C::ListShots, farm::ListShotsRequest());
      break;
    case kGetShot:
      unary(op, kClient, clients_, &C::GetShot, shotRequest());
      break;
    case kGetReport:
      unary(op, kClient, clients_, &C::GetReport, shotRequest());
      break;
    case kWatchShot: {
      // Until the shot ends, which in a fuzz input it mostly does not: a short look.
      const farm::ShotRequest request = shotRequest();
      download<farm::ShotSummary>(
          op, kClient, [&](auto* c) { return clientStub().WatchShot(c, request); }, std::chrono::milliseconds(20));
      break;
    }
    case kCancelShot:
      unary(op, kClient, clients_, &C::CancelShot, shotRequest());
      break;
    case kPauseShot:
      unary(op, kClient, clients_, &C::PauseShot, shotRequest());
      break;
    case kResumeShot:
      unary(op, kClient, clients_, &C::ResumeShot, shotRequest());
      break;
    case kRetryShot:
      unary(op, kClient, clients_, &C::RetryShot, shotRequest());
      break;
    case kFetchOutputs: {
      const farm::ShotRequest request = shotRequest();
      download<farm::OutputPart>(
          op, kClient, [&](auto* c) { return clientStub().FetchOutputs(c, request); }, kStream);
      break;
    }
    case kListWorkers:
      unary(op, kClient, clients_, &C::ListWorkers, farm::ListWorkersRequest());
      break;
    case kSetPriority:
      unary(op, kClient, clients_, &C::SetPriority, withShot(parsed<farm::PriorityRequest>(bytes)));
      break;
    case kRequeue:
      unary(op, kClient, clients_, &C::Requeue, withShot(parsed<farm::RequeueRequest>(bytes)));
      break;
    case kListBlocklist:
      unary(op, kClient, clients_, &C::ListBlocklist, parsed<farm::BlocklistRequest>(bytes));
      break;
    case kClearBlocklist:
      unary(op, kClient, clients_, &C::ClearBlocklist, parsed<farm::BlocklistRequest>(bytes));
      break;
    case kLeaseInputs: {
      const auto request = withAttempt(parsed<farm::LeaseInputsRequest>(bytes));
      download<farm::LeaseInputsPart>(
          op, kWorker, [&](auto* c) { return workerStub().LeaseInputs(c, request); }, kStream);
      break;
    }
    case kReportFollowUps:
      unary(op, kWorker, workers_, &W::ReportFollowUps, withAttempt(parsed<farm::FollowUpsRequest>(bytes)));
      break;
  }
}

namespace {

// A seed input, written call by call in the fuzzer's format.
class SeedInput {
 public:
  SeedInput& add(uint8_t op, const google::protobuf::Message& request) { return raw(op, request.SerializeAsString()); }
  // A client stream of the given parts.
  SeedInput& stream(uint8_t op, const std::vector<farm::ChunkPart>& parts) {
    std::string bytes;
    for (const farm::ChunkPart& part : parts) appendSized(bytes, part.SerializeAsString());
    return raw(op, bytes);
  }
  const std::string& bytes() const { return bytes_; }

 private:
  static void appendSized(std::string& out, const std::string& bytes) {
    out += static_cast<char>(bytes.size() & 0xff);
    out += static_cast<char>(bytes.size() >> 8);
    out += bytes;
  }
  SeedInput& raw(uint8_t op, const std::string& bytes) {
    bytes_ += static_cast<char>(op);
    appendSized(bytes_, bytes);
    return *this;
  }
  std::string bytes_;
};

// The parts of a chunk holding `bytes`, in two pieces.
std::vector<farm::ChunkPart> chunkOf(const std::string& bytes) {
  farm::ChunkPart first, second;
  first.mutable_ref()->set_sha256(farm::sha256Hex(bytes));
  first.mutable_ref()->set_size(static_cast<int64_t>(bytes.size()));
  first.set_data(bytes.substr(0, bytes.size() / 2));
  second.set_data(bytes.substr(bytes.size() / 2));
  return {first, second};
}

farm::ShotRequest shot(int64_t id) {
  farm::ShotRequest request;
  request.set_shot_id(id);
  return request;
}

}  // namespace

void writeRpcSeeds(const std::filesystem::path& folder) {
  std::filesystem::create_directories(folder);
  const auto write = [&](const std::string& name, const SeedInput& input) {
    std::ofstream(folder / name, std::ios::binary) << input.bytes();
  };
  farm::RegisterRequest registration;
  registration.set_name("fuzz-worker");
  registration.set_slots(2);
  registration.add_tags("gpu-less");
  farm::HeartbeatRequest heartbeat;
  heartbeat.set_progress(0.5);
  farm::CompleteRequest complete;
  complete.set_core_seconds(0.25);
  (*complete.mutable_metrics())["samples"] = 64;
  complete.set_log_tail("rendered\n");
  farm::FailRequest fail;
  fail.set_reason("the scene is broken");
  fail.set_failure_class(farm::FAILURE_BAD_INPUT);

  farm::SubmitRequest noop;
  noop.mutable_spec()->set_name("noop");
  noop.mutable_spec()->set_pipeline(farm::PIPELINE_NOOP);
  noop.mutable_spec()->set_noop_tasks(3);
  noop.mutable_spec()->set_max_attempts(2);
  noop.set_submit_key("seed-noop");
  farm::RequeueRequest requeue;
  requeue.set_task_id(1);
  write("noop_shot", SeedInput()
                         .add(kSubmit, noop)
                         .add(kRegister, registration)
                         .add(kLeaseTask, farm::LeaseRequest())
                         .add(kHeartbeat, heartbeat)
                         .add(kCompleteTask, complete)
                         .add(kLeaseTask, farm::LeaseRequest())
                         .add(kFailTask, fail)
                         .add(kLeaseTask, farm::LeaseRequest())
                         .add(kCompleteTask, complete)
                         .add(kGetShot, shot(0))
                         .add(kGetReport, shot(0))
                         .add(kRequeue, requeue)
                         .add(kListWorkers, farm::ListWorkersRequest())
                         .add(kListBlocklist, farm::BlocklistRequest())
                         .add(kClearBlocklist, farm::BlocklistRequest())
                         .add(kFetchOutputs, shot(0))
                         .add(kWatchShot, shot(0)));

  const std::string scene = R"({"camera": {"position": [0, 0, 3]}, "objects": []})";
  const std::vector<farm::ChunkPart> sceneChunk = chunkOf(scene);
  farm::SubmitRequest pt;
  farm::ShotSpec& spec = *pt.mutable_spec();
  spec.set_name("pt");
  spec.set_pipeline(farm::PIPELINE_PT);
  spec.set_scene("scene.json");
  spec.set_frame_end(1);
  spec.set_width(16);
  spec.set_height(16);
  spec.set_spp(1);
  spec.set_max_depth(2);
  spec.set_tile(8);
  spec.set_max_attempts(3);
  farm::InputFile& input = *spec.add_inputs();
  input.set_path("scene.json");
  *input.mutable_chunk() = sceneChunk.front().ref();
  farm::MissingInputsRequest missing;
  *missing.add_chunks() = sceneChunk.front().ref();
  farm::PriorityRequest priority;
  priority.set_priority(5);
  farm::GetChunkRequest get;
  get.set_sha256(sceneChunk.front().ref().sha256());
  const std::vector<farm::ChunkPart> tile = chunkOf(std::string(1024, '\x7f'));
  farm::CompleteRequest withOutput = complete;
  *withOutput.mutable_output() = tile.front().ref();
  farm::FollowUpsRequest followUps;
  farm::TaskParams& followUp = *followUps.add_follow_ups();
  followUp.set_role(farm::ROLE_RERENDER);
  followUp.set_pixel_mask(std::string(64, '\1'));
  followUp.mutable_window()->set_x1(8);
  followUp.mutable_window()->set_y1(8);
  write("pt_shot", SeedInput()
                       .add(kMissingInputs, missing)
                       .stream(kPutInput, sceneChunk)
                       .add(kSubmit, pt)
                       .add(kSetPriority, priority)
                       .add(kRegister, registration)
                       .add(kLeaseTask, farm::LeaseRequest())
                       .add(kGetChunk, get)
                       .add(kLeaseInputs, farm::LeaseInputsRequest())
                       .stream(kPutChunk, tile)
                       .add(kReportFollowUps, followUps)
                       .add(kCompleteTask, withOutput)
                       .add(kPauseShot, shot(0))
                       .add(kResumeShot, shot(0))
                       .add(kCancelShot, shot(0))
                       .add(kRetryShot, shot(0))
                       .add(kGetShot, shot(0)));

  // Finding 5 of docs/reliability.md: a heartbeat whose progress is no number.
  farm::HeartbeatRequest nanProgress;
  nanProgress.set_progress(std::nan(""));
  write("nan_progress", SeedInput()
                            .add(kSubmit, noop)
                            .add(kRegister, registration)
                            .add(kLeaseTask, farm::LeaseRequest())
                            .add(kHeartbeat, nanProgress));

  // The same calls from someone without the token.
  write("outsider", SeedInput()
                        .add(kRegister | kOutsider, registration)
                        .add(kSubmit | kOutsider, noop)
                        .add(kGetChunk | kOutsider, get)
                        .stream(kPutInput | kOutsider, sceneChunk)
                        .add(kListShots | kOutsider, farm::ListShotsRequest()));
}

}  // namespace pathfarm::fuzz
