#include "client/farm_client.h"

#include <chrono>
#include <cstdio>
#include <random>
#include <thread>

#include "image/atomic_file.h"
#include "proto/wire/chunk_transfer.h"
#include "proto/wire/connection.h"

namespace pathfarm::farm {

void FarmClient::check(const grpc::Status& status) const {
  if (!status.ok()) throw FarmError(status.error_code(), explainedError(status, tls_));
}

std::string frameFileName(int64_t frame) {
  char name[64];
  std::snprintf(name, sizeof name, "frame_%04lld.exr", static_cast<long long>(frame));
  return name;
}

FarmClient::FarmClient(const std::string& address, std::string token, const ClientTls& tls)
    : stub_(ClientService::NewStub(makeChannel(address, tls))), token_(std::move(token)), tls_(tls.enabled()) {}

std::unique_ptr<grpc::ClientContext> FarmClient::context(bool stream) const {
  auto context = std::make_unique<grpc::ClientContext>();
  // Streams (watching, fetching) last as long as they need; ordinary calls do not.
  if (!stream) context->set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(30));
  attachToken(*context, token_);
  return context;
}

int64_t FarmClient::submit(const ShotSpec& spec, std::string submitKey) {
  SubmitRequest request;
  *request.mutable_spec() = spec;
  if (submitKey.empty()) {
    std::random_device entropy;
    char key[33];
    std::snprintf(key, sizeof key, "%08x%08x%08x%08x", entropy(), entropy(), entropy(), entropy());
    submitKey = key;
  }
  request.set_submit_key(submitKey);
  constexpr int kTries = 3;
  for (int attempt = 1;; ++attempt) {
    SubmitReply reply;
    const grpc::Status status = stub_->Submit(context(false).get(), request, &reply);
    const bool retry = status.error_code() == grpc::StatusCode::DEADLINE_EXCEEDED ||
                       status.error_code() == grpc::StatusCode::UNAVAILABLE;
    if (!retry || attempt == kTries) {
      check(status);
      return reply.shot_id();
    }
    std::this_thread::sleep_for(std::chrono::seconds(attempt));
  }
}

std::vector<ShotSummary> FarmClient::shots() {
  ListShotsReply reply;
  check(stub_->ListShots(context(false).get(), ListShotsRequest(), &reply));
  return {reply.shots().begin(), reply.shots().end()};
}

ShotSummary FarmClient::watch(int64_t id, const std::function<void(const ShotSummary&)>& update) {
  ShotRequest request;
  request.set_shot_id(id);
  const auto call = context(true);
  auto reader = stub_->WatchShot(call.get(), request);
  ShotSummary summary;
  while (reader->Read(&summary)) update(summary);
  check(reader->Finish());
  return summary;
}

template <class Reply, class Method>
Reply FarmClient::aboutShot(Method method, int64_t id) {
  ShotRequest request;
  request.set_shot_id(id);
  Reply reply;
  check((stub_.get()->*method)(context(false).get(), request, &reply));
  return reply;
}

ShotReply FarmClient::shot(int64_t id) { return aboutShot<ShotReply>(&ClientService::Stub::GetShot, id); }
ShotReport FarmClient::report(int64_t id) { return aboutShot<ShotReport>(&ClientService::Stub::GetReport, id); }

ShotSummary FarmClient::cancel(int64_t id) {
  return aboutShot<ControlReply>(&ClientService::Stub::CancelShot, id).summary();
}
ShotSummary FarmClient::pause(int64_t id) {
  return aboutShot<ControlReply>(&ClientService::Stub::PauseShot, id).summary();
}
ShotSummary FarmClient::resume(int64_t id) {
  return aboutShot<ControlReply>(&ClientService::Stub::ResumeShot, id).summary();
}

ShotSummary FarmClient::setPriority(int64_t id, int priority) {
  PriorityRequest request;
  request.set_shot_id(id);
  request.set_priority(priority);
  ControlReply reply;
  check(stub_->SetPriority(context(false).get(), request, &reply));
  return reply.summary();
}

ShotSummary FarmClient::requeueTask(int64_t id, int64_t taskId) {
  RequeueRequest request;
  request.set_shot_id(id);
  request.set_task_id(taskId);
  return requeue(request);
}

ShotSummary FarmClient::requeueFrame(int64_t id, int64_t frame) {
  RequeueRequest request;
  request.set_shot_id(id);
  request.set_frame(frame);
  return requeue(request);
}

ShotSummary FarmClient::requeue(const RequeueRequest& request) {
  ControlReply reply;
  check(stub_->Requeue(context(false).get(), request, &reply));
  return reply.summary();
}

std::vector<ChunkRef> FarmClient::missingInputs(const std::vector<ChunkRef>& chunks) {
  MissingInputsRequest request;
  for (const ChunkRef& ref : chunks) *request.add_chunks() = ref;
  MissingInputsReply reply;
  check(stub_->MissingInputs(context(false).get(), request, &reply));
  return {reply.chunks().begin(), reply.chunks().end()};
}

void FarmClient::putInput(const std::string& bytes, const ChunkRef& ref) {
  const auto call = context(true);
  PutInputReply reply;
  auto writer = stub_->PutInput(call.get(), &reply);
  sendChunk(*writer, ref, bytes);
  writer->WritesDone();
  check(writer->Finish());
}

std::vector<BlocklistEntry> FarmClient::blocklist(int64_t shotId) {
  BlocklistRequest request;
  request.set_shot_id(shotId);
  BlocklistReply reply;
  check(stub_->ListBlocklist(context(false).get(), request, &reply));
  return {reply.entries().begin(), reply.entries().end()};
}

std::vector<BlocklistEntry> FarmClient::clearBlocklist(int64_t shotId, int64_t workerId) {
  BlocklistRequest request;
  request.set_shot_id(shotId);
  request.set_worker_id(workerId);
  BlocklistReply reply;
  check(stub_->ClearBlocklist(context(false).get(), request, &reply));
  return {reply.entries().begin(), reply.entries().end()};
}

ShotSummary FarmClient::retry(int64_t id) {
  return aboutShot<ControlReply>(&ClientService::Stub::RetryShot, id).summary();
}

std::vector<std::filesystem::path> FarmClient::fetch(int64_t id, const std::filesystem::path& folder) {
  std::filesystem::create_directories(folder);
  return fetchFrames(id, false, [&](int64_t frame) { return folder / frameFileName(frame); });
}

std::vector<std::filesystem::path> FarmClient::fetchReferences(
    int64_t id, const std::function<std::filesystem::path(int64_t frame)>& fileOf) {
  return fetchFrames(id, true, fileOf);
}

std::vector<std::filesystem::path> FarmClient::fetchFrames(
    int64_t id, bool references, const std::function<std::filesystem::path(int64_t frame)>& fileOf) {
  ShotRequest request;
  request.set_shot_id(id);
  request.set_references(references);
  const auto call = context(true);
  auto reader = stub_->FetchOutputs(call.get(), request);
  std::vector<std::filesystem::path> files;
  // Each frame's chunk starts with a part that carries its reference; its file is written
  // as the parts come, and appears once the whole chunk checks out.
  std::optional<IncomingChunk> chunk;
  try {
    OutputPart part;
    while (reader->Read(&part)) {
      if (part.part().has_ref()) {
        if (chunk) chunk->commit();
        files.push_back(fileOf(part.frame()));
        chunk.emplace(part.part().ref(), kMaxChunkBytes, files.back(), AtomicFileWriter::Sync::Yes, "write frame");
      }
      if (!chunk) throw ChunkError("the output stream began without a chunk reference");
      chunk->append(part.part().data());
    }
    if (chunk) chunk->commit();
  } catch (const ChunkError& e) {
    call->TryCancel();
    reader->Finish();
    throw FarmError(grpc::StatusCode::DATA_LOSS, e.what());
  }
  check(reader->Finish());
  return files;
}

std::vector<WorkerInfo> FarmClient::workers() {
  ListWorkersReply reply;
  check(stub_->ListWorkers(context(false).get(), ListWorkersRequest(), &reply));
  return {reply.workers().begin(), reply.workers().end()};
}

}  // namespace pathfarm::farm
