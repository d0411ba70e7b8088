#include "scheduler/scheduler_server.h"

#include <algorithm>

#include <grpcpp/grpcpp.h>
#include <spdlog/spdlog.h>

#include "proto/wire/connection.h"
#include "scheduler/http/dashboard_api.h"
#include "scheduler/exclusive_database.h"
#include "scheduler/scheduler_services.h"

namespace pathfarm::farm {

namespace {

// One listening address against the farm's protection: beyond loopback a token is always
// needed, and, without TLS, the user's word that the token and the farm's data may cross
// the network in clear.
void checkAddress(const std::string& option, const std::string& address, const SchedulerOptions& o) {
  if (address.empty() || isLoopbackAddress(address)) return;
  if (o.token.empty())
    throw std::runtime_error(option + " " + address +
                             " reaches beyond this machine: give an access token (--token-file or PATHFARM_TOKEN[_FILE])");
  if (!o.tls.enabled() && !o.insecure)
    throw std::runtime_error(option + " " + address +
                             " reaches beyond this machine unencrypted (the token and every frame would cross the "
                             "network in clear): give a certificate (--tls-cert, --tls-key), or pass --insecure to "
                             "serve there anyway");
}

}  // namespace

void checkExposure(const SchedulerOptions& o) {
  checkAddress("--listen", o.listen, o);
  checkAddress("--http", o.http, o);
}

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
        state(o.database.string(), o.farm, farmClockSeconds()),
        store(o.store),
        workerService({state, store, signal, o.workerToken.empty() ? o.token : o.workerToken, o.limits}),
        clientService({state, store, signal, o.token, o.limits}),
        thumbnails(store) {}
};

SchedulerServer::SchedulerServer(SchedulerOptions options) : options_(std::move(options)) {
  checkExposure(options_);
  services_ = std::make_unique<Services>(options_);
  if (const size_t removed = services_->store.removeAbandonedWrites(); removed > 0)
    spdlog::info("removed {} chunk(s) left half-written in the store by a scheduler that was killed", removed);
  // Before any worker can store one of them again.
  size_t leftReleased = 0;
  for (const std::string& sha : services_->state.releasedChunks())
    if (services_->store.has(sha)) {
      services_->store.remove(sha);
      ++leftReleased;
    }
  if (leftReleased > 0)
    spdlog::info("removed {} released chunk(s) left in the store by a scheduler that was killed", leftReleased);
  grpc::ServerBuilder builder;
  configureServer(builder);
  builder.AddListeningPort(options_.listen, serverCredentials(options_.tls), &port_);
  builder.RegisterService(&services_->workerService);
  builder.RegisterService(&services_->clientService);
  server_ = builder.BuildAndStart();
  if (!server_ || port_ == 0) throw std::runtime_error("cannot listen on " + options_.listen);

  // The one checker of timeouts (leases not renewed, tasks that stopped progressing) and
  // of retention.
  checker_ = std::thread([this] {
    const double period = std::clamp(options_.farm.leaseSeconds / 10, 0.05, 1.0);
    const double retentionPeriod = std::clamp(options_.farm.retainSeconds / 4, 0.1, 300.0);
    double nextRetention = 0;
    while (!stopping_) {
      try {
        if (services_->state.expireLeases(farmClockSeconds()) > 0) services_->signal.notify();
        for (const std::string& sha : services_->state.takeReleasedChunks()) services_->store.remove(sha);
        if (options_.farm.retainSeconds > 0 && farmClockSeconds() >= nextRetention) {
          collectGarbage();
          nextRetention = farmClockSeconds() + retentionPeriod;
        }
      } catch (const std::exception& e) {
        spdlog::error("lease checker: {}", e.what());
      }
      std::unique_lock lock(checkerMutex_);
      checkerWake_.wait_for(lock, std::chrono::duration<double>(period), [this] { return stopping_.load(); });
    }
  });
  if (!options_.http.empty()) {
    http_ = std::make_unique<HttpServer>(options_.http, options_.token, options_.tls, [this](httplib::Server& server) {
      serveMetrics(server, [this] {
        FarmMetrics metrics = services_->state.metrics(farmClockSeconds());
        metrics.chunkBytesIn = services_->store.bytesIn();
        metrics.chunkBytesOut = services_->store.bytesOut();
        return prometheusText(metrics);
      });
      Services& s = *services_;
      serveDashboard(server, {s.state, s.store, s.signal, s.thumbnails});
    });
  }
  spdlog::info("scheduler listening on {} (database {}, store {}{}{})", address(), options_.database.string(),
               options_.store.string(), options_.token.empty() ? ", no access token" : ", token required",
               options_.tls.enabled() ? ", TLS" : "");
}

SchedulerServer::~SchedulerServer() { shutdown(); }

void SchedulerServer::collectGarbage() {
  const FarmState::Collected collected = services_->state.collectGarbage(farmClockSeconds());
  // The rows are gone first: a crash here leaves files no row names, never a row without its file.
  for (const std::string& sha : collected.chunks) services_->store.remove(sha);
  if (!collected.shots.empty() || !collected.chunks.empty())
    spdlog::info("retention: deleted {} finished shot(s) and {} chunk(s)", collected.shots.size(),
                 collected.chunks.size());
}

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
  {
    const std::lock_guard lock(checkerMutex_);
    checkerWake_.notify_all();
  }
  if (checker_.joinable()) checker_.join();
}

}  // namespace pathfarm::farm
