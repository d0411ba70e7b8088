// Scene files a client uploads before it submits (inputs without shared storage), and the
// reference frames its cache held.
#include "proto/wire/input_files.h"
#include "scheduler/quoted_text.h"
#include "scheduler/service_chunks.h"
#include "scheduler/service_guard.h"

namespace pathfarm::farm {

grpc::Status ClientServiceImpl::MissingInputs(grpc::ServerContext* context, const MissingInputsRequest* request,
                                              MissingInputsReply* reply) {
  return guarded(c_, context, [&] {
    for (const ChunkRef& ref : request->chunks()) {
      if (!isSha256Hex(ref.sha256()))
        return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, "not a SHA-256 digest: " + ref.sha256());
      if (!c_.state.hasChunk(ref.sha256()) || !c_.store.has(ref.sha256())) *reply->add_chunks() = ref;
    }
    return grpc::Status::OK;
  });
}

grpc::Status ClientServiceImpl::PutInput(grpc::ServerContext* context, grpc::ServerReader<ChunkPart>* reader,
                                         PutInputReply* reply) {
  return guarded(c_, context, [&] {
    *reply->mutable_ref() = storeReceivedChunk(*reader, c_);
    return grpc::Status::OK;
  });
}

std::string ClientServiceImpl::inputProblem(const ShotSpec& spec) const {
  try {
    checkInputFiles(spec);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  for (const InputFile& file : spec.inputs()) {
    if (!c_.state.hasChunk(file.chunk().sha256()) || !c_.store.has(file.chunk().sha256()))
      return "scene file " + quotedInput(file.path()) + " (" + quotedInput(file.chunk().sha256()) + ") was not uploaded";
  }
  for (const KnownReference& reference : spec.known_references()) {
    const std::string& sha = reference.chunk().sha256();
    if (!isSha256Hex(sha) || !c_.state.hasChunk(sha) || !c_.store.has(sha))
      return "the reference of frame " + std::to_string(reference.frame()) + " (" + quotedInput(sha) +
             ") was not uploaded";
  }
  return "";
}

}  // namespace pathfarm::farm
