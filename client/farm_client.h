#pragma once
// The client side of ClientService for the CLI and tools: submit, follow, control and
// fetch shots. Every call carries the access token; a refused or failed call throws
// FarmError with the scheduler's message.
#include <filesystem>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "pathfarm/client_service.grpc.pb.h"
#include "proto/wire/tls.h"

namespace pathfarm::farm {

class FarmError : public std::runtime_error {
 public:
  FarmError(grpc::StatusCode code, const std::string& message) : std::runtime_error(message), code_(code) {}
  grpc::StatusCode code() const { return code_; }

 private:
  grpc::StatusCode code_;
};

class FarmClient {
 public:
  // Over TLS when `tls` names the CA of the scheduler's certificate.
  FarmClient(const std::string& address, std::string token, const ClientTls& tls = {});

  // Queues the shot under `submitKey` (a random one when empty), retrying a call that
  // timed out or found the scheduler away with the same key, so it makes one shot.
  int64_t submit(const ShotSpec& spec, std::string submitKey = "");
  // Of these chunks, the ones the scheduler's store lacks.
  std::vector<ChunkRef> missingInputs(const std::vector<ChunkRef>& chunks);
  // Stores one scene file's bytes (streamed in bounded parts, verified on receipt).
  void putInput(const std::string& bytes, const ChunkRef& ref);
  std::vector<ShotSummary> shots();
  ShotReply shot(int64_t id);
  ShotReport report(int64_t id);
  // Calls `update` with each summary until the shot ends; returns the last one.
  ShotSummary watch(int64_t id, const std::function<void(const ShotSummary&)>& update);
  ShotSummary cancel(int64_t id);
  ShotSummary pause(int64_t id);
  ShotSummary resume(int64_t id);
  ShotSummary retry(int64_t id);
  ShotSummary setPriority(int64_t id, int priority);
  ShotSummary requeueTask(int64_t id, int64_t taskId);
  ShotSummary requeueFrame(int64_t id, int64_t frame);
  std::vector<BlocklistEntry> blocklist(int64_t shotId);  // 0: every shot
  std::vector<BlocklistEntry> clearBlocklist(int64_t shotId, int64_t workerId);  // what is left
  // Writes every finished frame as DIR/frame_NNNN.exr (verified, atomically); returns the files.
  std::vector<std::filesystem::path> fetch(int64_t id, const std::filesystem::path& folder);
  // Writes each reference frame of the shot (rendered or given) to fileOf(frame), the same way.
  std::vector<std::filesystem::path> fetchReferences(int64_t id,
                                                     const std::function<std::filesystem::path(int64_t frame)>& fileOf);
  std::vector<WorkerInfo> workers();

 private:
  std::unique_ptr<grpc::ClientContext> context(bool stream) const;
  // One unary call about a shot.
  template <class Reply, class Method>
  Reply aboutShot(Method method, int64_t id);
  ShotSummary requeue(const RequeueRequest& request);
  std::vector<std::filesystem::path> fetchFrames(int64_t id, bool references,
                                                 const std::function<std::filesystem::path(int64_t frame)>& fileOf);
  // Throws FarmError for a failed call, its message saying what to do about trouble with
  // the connection itself (connection.h).
  void check(const grpc::Status& status) const;
  std::unique_ptr<ClientService::Stub> stub_;
  std::string token_;
  bool tls_ = false;
};

std::string frameFileName(int64_t frame);

}  // namespace pathfarm::farm
