#pragma once
// The scheduler process: FarmState on SQLite, the chunk store, both gRPC services, and
// the one checker that ends expired leases and hung tasks.
#include <atomic>
#include <condition_variable>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "scheduler/farm_state.h"
#include "proto/wire/tls.h"
#include "scheduler/http/http_server.h"

namespace grpc {
class Server;
}

namespace pathfarm::farm {

struct SchedulerOptions {
  std::string listen = "127.0.0.1:7700";  // port 0: any free port (see port())
  std::filesystem::path database = "farm.db";
  std::filesystem::path store = "chunks";
  std::string token;  // what clients (and, without a worker token, workers) show; empty: no access control
  // What workers show instead, when given: a worker's credential then cannot submit, fetch
  // or control shots, and a client's cannot lease, complete or fail tasks.
  std::string workerToken;
  // gRPC over TLS with this certificate (and the HTTP side over HTTPS with it); client
  // certificates are required when it names a client CA.
  ServerTls tls;
  // Serve beyond loopback without TLS (the token and every chunk cross the network in
  // clear): refused without it.
  bool insecure = false;
  // HOST:PORT serving the dashboard and /metrics over HTTP (port 0: any free port); empty:
  // none. With a token, the dashboard's API asks for it (/metrics does not).
  std::string http;
  ShotLimits limits;  // what one submitted shot may ask for
  FarmSettings farm;
};

// Beyond loopback the scheduler needs a token, and TLS or the user's word (`insecure`);
// throws std::runtime_error saying which is missing, for gRPC and the HTTP side alike.
void checkExposure(const SchedulerOptions& options);

class SchedulerServer {
 public:
  // Opens the database and store and starts serving; throws std::runtime_error when the
  // address cannot be bound, another scheduler has the database, or an address (gRPC or
  // HTTP) reaches beyond loopback without a token, or without `insecure`.
  explicit SchedulerServer(SchedulerOptions options);
  ~SchedulerServer();

  int port() const { return port_; }
  int httpPort() const;  // 0 without an HTTP side
  std::string address() const;
  void wait();      // until shutdown()
  void shutdown();  // stops accepting calls, ends the open ones, stops the checker

 private:
  struct Services;
  // Deletes what retention (FarmSettings::retainSeconds) lets go, files included.
  void collectGarbage();
  SchedulerOptions options_;
  std::unique_ptr<Services> services_;
  std::unique_ptr<grpc::Server> server_;
  std::unique_ptr<HttpServer> http_;
  int port_ = 0;
  std::atomic<bool> stopping_{false};
  // Wakes the checker from its pause when shutdown() sets stopping_.
  std::mutex checkerMutex_;
  std::condition_variable checkerWake_;
  std::thread checker_;
};

}  // namespace pathfarm::farm
