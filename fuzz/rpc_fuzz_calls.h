#pragma once
// The calls rpc_handlers_fuzzer.cpp makes: one per RPC of the scheduler's two services,
// each from request bytes, with what a real caller would remember between calls (its
// worker session, the last attempt it leased, the last shot it submitted).
//
// Unary calls go straight to the handlers with the metadata a client would send (a gRPC
// round trip per call would cost most of the fuzzer's time); streams need gRPC's readers
// and writers and go through an in-process server over the same services.
#include <grpcpp/grpcpp.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string_view>
#include <utility>

#include "pathfarm/client_service.grpc.pb.h"
#include "pathfarm/worker_service.grpc.pb.h"
#include "proto/wire/connection.h"
#include "scheduler/scheduler_services.h"

namespace pathfarm::fuzz {

// The access token of the fuzzed farm, for clients and workers alike.
inline constexpr const char* kFuzzToken = "fuzz-token";

class RpcCalls {
 public:
  static constexpr int kCalls = 26;
  static constexpr uint8_t kOutsider = 0x80;  // the call carries neither token nor session

  // `streamChannel` opens the in-process channel, the first time a stream is called.
  RpcCalls(farm::WorkerServiceImpl& workers, farm::ClientServiceImpl& clients,
           std::function<std::shared_ptr<grpc::Channel>()> streamChannel);
  // Runs call `(op & ~kOutsider) % kCalls` with the request parsed from `request` (empty
  // if it does not parse); the status is any, the reply is read whole.
  void run(uint8_t op, std::string_view request);

 private:
  template <class Service, class Request, class Reply>
  using Handler = grpc::Status (Service::*)(grpc::ServerContext*, const Request*, Reply*);

  grpc::Status call(uint8_t op, bool worker, const std::function<grpc::Status(grpc::ServerContext*)>& handle);
  // A unary handler called with the request; its status and reply.
  template <class Service, class Request, class Reply>
  std::pair<grpc::Status, Reply> unary(uint8_t op, bool worker, Service& service,
                                       Handler<Service, Request, Reply> handler, const Request& request);
  void prepare(grpc::ClientContext& context, uint8_t op, bool worker) const;
  // A client stream of the parts in `parts` (see rpc_handlers_fuzzer.cpp).
  template <class Reply, class Open>
  void upload(uint8_t op, bool worker, Open open, std::string_view parts);
  // A server stream read whole, or until `limit`.
  template <class Part, class Open>
  void download(uint8_t op, bool worker, Open open, std::chrono::milliseconds limit);
  farm::WorkerService::Stub& workerStub();
  farm::ClientService::Stub& clientStub();

  farm::WorkerServiceImpl& workers_;
  farm::ClientServiceImpl& clients_;
  std::function<std::shared_ptr<grpc::Channel>()> streamChannel_;
  std::unique_ptr<farm::WorkerService::Stub> workerStub_;
  std::unique_ptr<farm::ClientService::Stub> clientStub_;
  farm::WorkerSession session_;  // workerId 0: none registered yet
  int64_t lastAttempt_ = 0;
  int64_t lastShot_ = 0;
};

// Writes the seed corpus (fuzz/corpus/rpc_handlers): a worker's life on a noop shot and on
// a small pt shot, chunks put and fetched, the client's controls, and the inputs of
// findings since fixed.
void writeRpcSeeds(const std::filesystem::path& folder);

}  // namespace pathfarm::fuzz
