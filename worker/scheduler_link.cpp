#include "worker/scheduler_link.h"

#include <optional>
#include <thread>

#include "proto/wire/chunk_transfer.h"
#include "proto/wire/connection.h"

namespace pathfarm::farm {
namespace {

constexpr double kCallSeconds = 10;      // an ordinary call
constexpr double kTransferSeconds = 300;  // a chunk of a large frame on a slow link

}  // namespace

SchedulerLink::SchedulerLink(const std::string& address, std::string token, const ClientTls& tls)
    : channel_(makeChannel(address, tls)), stub_(WorkerService::NewStub(channel_)), token_(std::move(token)) {}

void SchedulerLink::pause(std::chrono::milliseconds delay) {
  const auto until = std::chrono::system_clock::now() + delay;
  // WaitForConnected polls the connection and starts attempts; a connection that is up
  // already (the call failed for another reason) gets the plain wait.
  if (channel_->GetState(false) != GRPC_CHANNEL_READY && channel_->WaitForConnected(until)) return;
  std::this_thread::sleep_until(until);
}

Backoff SchedulerLink::backoff() {
  return Backoff([this](std::chrono::milliseconds delay) { pause(delay); });
}

std::unique_ptr<grpc::ClientContext> SchedulerLink::context(double seconds, WorkerSession* used) const {
  auto context = std::make_unique<grpc::ClientContext>();
  context->set_deadline(std::chrono::system_clock::now() +
                        std::chrono::milliseconds(static_cast<int64_t>(seconds * 1000)));
  attachToken(*context, token_);
  const std::lock_guard lock(sessionMutex_);
  attachSession(*context, session_);
  if (used) *used = session_;
  return context;
}

grpc::Status SchedulerLink::registerWorker(const std::string& name, int slots, const std::vector<std::string>& tags,
                                           RegisterReply& reply) {
  RegisterRequest request;
  request.set_name(name);
  request.set_slots(slots);
  for (const std::string& tag : tags) request.add_tags(tag);
  const grpc::Status status = stub_->Register(context(kCallSeconds).get(), request, &reply);
  if (status.ok()) {
    const std::lock_guard lock(sessionMutex_);
    session_ = {reply.worker_id(), reply.session_key()};
  }
  return status;
}

grpc::Status SchedulerLink::registerAgain(const WorkerSession& refused, const std::string& name, int slots,
                                          const std::vector<std::string>& tags) {
  const std::lock_guard lock(registerMutex_);
  {
    const std::lock_guard sessionLock(sessionMutex_);
    if (session_.workerId != refused.workerId || session_.key != refused.key) return grpc::Status::OK;
  }
  RegisterReply reply;
  return registerWorker(name, slots, tags, reply);
}

grpc::Status SchedulerLink::lease(double waitSeconds, LeaseReply& reply, WorkerSession& used) {
  const auto call = context(kCallSeconds + waitSeconds, &used);
  LeaseRequest request;
  request.set_worker_id(used.workerId);
  request.set_wait_seconds(waitSeconds);
  {
    const std::lock_guard lock(mutex_);
    if (leasingStopped_) return {grpc::StatusCode::CANCELLED, "the worker is stopping"};
    pendingLeases_.insert(call.get());
  }
  const grpc::Status status = stub_->LeaseTask(call.get(), request, &reply);
  const std::lock_guard lock(mutex_);
  pendingLeases_.erase(call.get());
  return status;
}

void SchedulerLink::stopLeasing() {
  const std::lock_guard lock(mutex_);
  leasingStopped_ = true;
  for (grpc::ClientContext* call : pendingLeases_) call->TryCancel();
}

grpc::Status SchedulerLink::heartbeat(int64_t attemptId, double progress, HeartbeatReply& reply) {
  HeartbeatRequest request;
  request.set_attempt_id(attemptId);
  request.set_progress(progress);
  return stub_->Heartbeat(context(kCallSeconds).get(), request, &reply);
}

grpc::Status SchedulerLink::leaseInputs(Lease& lease) {
  LeaseInputsRequest request;
  request.set_attempt_id(lease.attempt_id());
  const auto call = context(kTransferSeconds);
  auto reader = stub_->LeaseInputs(call.get(), request);
  LeaseInputsPart part;
  while (reader->Read(&part)) {
    for (ChunkRef& input : *part.mutable_inputs()) *lease.add_inputs() = std::move(input);
    for (TaskParams& params : *part.mutable_input_params()) *lease.add_input_params() = std::move(params);
    for (const int kind : part.input_kinds()) lease.add_input_kinds(static_cast<TaskKind>(kind));
  }
  return reader->Finish();
}

grpc::Status SchedulerLink::reportFollowUps(const FollowUpsRequest& request, ReportReply& reply) {
  return stub_->ReportFollowUps(context(kCallSeconds).get(), request, &reply);
}

grpc::Status SchedulerLink::complete(const CompleteRequest& request, ReportReply& reply) {
  // The scheduler reads the whole output before it answers: a large frame's chunk.
  return stub_->CompleteTask(context(kTransferSeconds).get(), request, &reply);
}

grpc::Status SchedulerLink::fail(const FailRequest& request, ReportReply& reply) {
  return stub_->FailTask(context(kCallSeconds).get(), request, &reply);
}

template <class Send>
grpc::Status SchedulerLink::put(ChunkRef& stored, Send send) {
  const auto call = context(kTransferSeconds);
  PutChunkReply reply;
  auto writer = stub_->PutChunk(call.get(), &reply);
  send(*writer);
  writer->WritesDone();
  const grpc::Status status = writer->Finish();
  if (status.ok()) stored = reply.ref();
  return status;
}

grpc::Status SchedulerLink::putChunk(const std::string& bytes, ChunkRef& stored) {
  ChunkRef ref;
  ref.set_sha256(sha256Hex(bytes));
  ref.set_size(static_cast<int64_t>(bytes.size()));
  return put(stored, [&](auto& writer) { sendChunk(writer, ref, bytes); });
}

grpc::Status SchedulerLink::putChunkFile(const std::filesystem::path& file, ChunkRef& stored) {
  try {
    const ChunkRef ref = refOfFile(file);
    return put(stored, [&](auto& writer) { sendFileChunk(writer, ref, file); });
  } catch (const ChunkError& e) {
    return {grpc::StatusCode::INTERNAL, e.what()};
  }
}

grpc::Status SchedulerLink::getChunk(const std::string& sha256, std::string& bytes) {
  GetChunkRequest request;
  request.set_sha256(sha256);
  const auto call = context(kTransferSeconds);
  auto reader = stub_->GetChunk(call.get(), request);
  ChunkAssembler chunk;
  try {
    ChunkPart part;
    while (reader->Read(&part)) {
      if (!chunk.started()) chunk.start(part.ref(), kMaxChunkBytes);
      chunk.append(part.data());
    }
  } catch (const ChunkError& e) {
    call->TryCancel();  // the bytes are bad: stop the stream
    reader->Finish();
    return {grpc::StatusCode::DATA_LOSS, e.what()};
  }
  // The stream ended: its status (a refusal, a dropped connection) explains a short chunk.
  const grpc::Status status = reader->Finish();
  if (!status.ok()) return status;
  if (!chunk.started()) return {grpc::StatusCode::DATA_LOSS, "empty chunk stream for " + sha256};
  if (chunk.ref().sha256() != sha256)
    return {grpc::StatusCode::DATA_LOSS, "asked for chunk " + sha256 + ", received " + chunk.ref().sha256()};
  try {
    bytes = chunk.finish();
  } catch (const ChunkError& e) {
    return {grpc::StatusCode::DATA_LOSS, e.what()};
  }
  return status;
}

grpc::Status SchedulerLink::getChunkInto(const std::string& sha256, ChunkStore& store) {
  GetChunkRequest request;
  request.set_sha256(sha256);
  const auto call = context(kTransferSeconds);
  auto reader = stub_->GetChunk(call.get(), request);
  ChunkPart part;
  if (!reader->Read(&part)) {  // a refusal, or a dropped connection
    const grpc::Status status = reader->Finish();
    return status.ok() ? grpc::Status(grpc::StatusCode::DATA_LOSS, "empty chunk stream for " + sha256) : status;
  }
  std::optional<ChunkStore::Incoming> incoming;
  try {
    if (part.ref().sha256() != sha256) throw ChunkError("asked for chunk " + sha256 + ", received " + part.ref().sha256());
    incoming.emplace(store, part.ref(), kMaxChunkBytes);
    do {
      incoming->append(part.data());
    } while (reader->Read(&part));
  } catch (const ChunkError& e) {
    call->TryCancel();  // the bytes are bad: stop the stream
    reader->Finish();
    return {grpc::StatusCode::DATA_LOSS, e.what()};
  }
  // The stream ended: its status (a refusal, a dropped connection) explains a short chunk.
  if (const grpc::Status status = reader->Finish(); !status.ok()) return status;
  try {
    incoming->commit();
  } catch (const ChunkError& e) {
    return {grpc::StatusCode::DATA_LOSS, e.what()};
  }
  return grpc::Status::OK;
}

}  // namespace pathfarm::farm
