#include "scheduler/scheduler_server.h"

#include <algorithm>

#include <grpcpp/grpcpp.h>
#include <spdlog/spdlog.h>

#include "proto/wire/connection.h"
#include "scheduler/dashboard_api.h"
#include "scheduler/exclusive_database.h"
#include "scheduler/scheduler_services.h"

namespace pathfarm::farm {

namespace {

// The listening address against the farm's protection: beyond loopback a token is always
// needed, and, since the channel is not encrypted, the user's word that this is wanted.
void checkExposure(const SchedulerOptions& o) {
  if (isLoopbackAddress(o.listen)) return;
  if (o.token.empty())
    throw std::runtime_error("--listen " + o.listen +
                             " reaches beyond this machine: give an access token (--token-file or PATHFARM_TOKEN[_FILE])");
  if (!o.insecure)
    throw std::runtime_error("--listen " + o.listen +
                             " reaches beyond this machine over an unencrypted channel (the token and every frame "
                             "cross the network in clear); pass --insecure to serve there anyway");
}

// The dashboard's API on the HTTP side asks for the same token as gRPC (/metrics asks
// for none): beyond loopback it needs one, and, as plain HTTP sends it in clear, the
// user's word.
void checkHttpExposure(const SchedulerOptions& o) {
  if (o.http.empty() || isLoopbackAddress(o.http)) return;
  if (o.token.empty())
    throw std::runtime_error("--http " + o.http +
                             " reaches beyond this machine: give an access token (--token-file or "
                             "PATHFARM_TOKEN[_FILE]) for the dashboard to ask for");
  if (!o.insecure)
    throw std::runtime_error("--http " + o.http +
                             " reaches beyond this machine over plain HTTP (the token, the farm's data and /metrics, "
                             "which asks for no token, cross the network in clear); pass --insecure to serve there "
                             "anyway");
}

}  // namespace

struct SchedulerServer::Services {
  ExclusiveDatabase exclusive;  // first: before the database is opened
  FarmState state;
  ChunkStore store;
  FarmSignal signal;
  WorkerServiceImpl workerService;
  ClientServiceImpl clientService;
  ThumbnailCache thumbnails;

  explicit Services(const SchedulerOptions& o)
      : exclusive(o.database),
        state(o.database.string(), o.farm, wallClockSeconds()),
        store(o.store),
        workerService({state, store, signal, o.token, o.limits}),
        clientService({state, store, signal, o.token, o.limits}),
        thumbnails(store) {}
};

SchedulerServer::SchedulerServer(SchedulerOptions options) : options_(std::move(options)) {
  checkExposure(options_);
  checkHttpExposure(options_);
  services_ = std::make_unique<Services>(options_);
  grpc::ServerBuilder builder;
  configureServer(builder);
  builder.AddListeningPort(options_.listen, grpc::InsecureServerCredentials(), &port_);
  builder.RegisterService(&services_->workerService);
  builder.RegisterService(&services_->clientService);
  server_ = builder.BuildAndStart();
  if (!server_ || port_ == 0) throw std::runtime_error("cannot listen on " + options_.listen);

  // The one checker of timeouts: leases not renewed, tasks that stopped progressing.
  checker_ = std::thread([this] {
    const double period = std::clamp(options_.farm.leaseSeconds / 10, 0.05, 1.0);
    while (!stopping_) {
      try {
        if (services_->state.expireLeases(wallClockSeconds()) > 0) services_->signal.notify();
      } catch (const std::exception& e) {
        spdlog::error("lease checker: {}", e.what());
      }
      std::this_thread::sleep_for(std::chrono::duration<double>(period));
    }
  });
  if (!options_.http.empty()) {
    http_ = std::make_unique<HttpServer>(options_.http, options_.token, [this](httplib::Server& server) {
      serveMetrics(server, [this] {
        FarmMetrics metrics = services_->state.metrics(wallClockSeconds());
        metrics.chunkBytesIn = services_->store.bytesIn();
        metrics.chunkBytesOut = services_->store.bytesOut();
        return prometheusText(metrics);
      });
      Services& s = *services_;
      serveDashboard(server, {s.state, s.store, s.signal, s.thumbnails});
    });
  }
  spdlog::info("scheduler listening on {} (database {}, store {}{})", address(), options_.database.string(),
               options_.store.string(), options_.token.empty() ? ", no access token" : ", token required");
}

SchedulerServer::~SchedulerServer() { shutdown(); }

std::string SchedulerServer::address() const {
  const auto colon = options_.listen.rfind(':');
  return options_.listen.substr(0, colon) + ":" + std::to_string(port_);
}

void SchedulerServer::wait() {
  if (server_) server_->Wait();
}

int SchedulerServer::httpPort() const { return http_ ? http_->port() : 0; }

void SchedulerServer::shutdown() {
  if (stopping_.exchange(true)) return;
  http_.reset();
  services_->signal.notify();
  // Open long-polls and watches get a moment to return, then are cut.
  server_->Shutdown(std::chrono::system_clock::now() + std::chrono::seconds(1));
  if (checker_.joinable()) checker_.join();
}

}  // namespace pathfarm::farm
