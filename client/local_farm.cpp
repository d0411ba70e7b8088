#include "client/local_farm.h"

#include <unistd.h>

#include <signal.h>
#include <spdlog/spdlog.h>

#include <stdexcept>
#include <thread>

namespace pathfarm::farm {

LocalFarm::LocalFarm(LocalFarmOptions options) : options_(std::move(options)), token_(randomToken()) {
  std::filesystem::create_directories(options_.folder / "logs");
  SchedulerOptions scheduler;
  scheduler.listen = "127.0.0.1:0";
  scheduler.database = options_.folder / "farm.db";
  scheduler.store = options_.folder / "chunks";
  scheduler.token = token_;
  scheduler.farm = options_.farm;
  scheduler.limits = options_.limits;
  scheduler.http = options_.http;
  scheduler_ = std::make_unique<SchedulerServer>(scheduler);
  address_ = scheduler_->address();
  if (!options_.http.empty()) {
    // The token rides in the link's fragment, which a browser keeps to itself; the page
    // takes it from there.
    const std::string host = options_.http.substr(0, options_.http.rfind(':'));
    spdlog::info("dashboard: http://{}:{}/#token={}", host, scheduler_->httpPort(), token_);
  }

  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int threads = options_.threadsPerWorker > 0 ? options_.threadsPerWorker : std::max(1, cores / options_.workers);
  for (int i = 0; i < options_.workers; ++i) {
    const std::string name = "local-" + std::to_string(i);
    workers_.emplace_back(
        std::vector<std::string>{options_.executable, "worker", "--scheduler", address_, "--threads",
                                 std::to_string(threads), "--name", name, "--cache",
                                 (options_.folder / "cache" / name).string(), "--parent", std::to_string(getpid())},
        (options_.folder / "logs" / (name + ".log")).string(), std::vector<std::string>{"PATHFARM_TOKEN=" + token_});
  }
  spdlog::info("local farm: scheduler on {}, {} workers with {} threads each (logs in {})", address_,
               options_.workers, threads, (options_.folder / "logs").string());
}

LocalFarm::~LocalFarm() { stop(); }

FarmClient LocalFarm::client() const { return FarmClient(address_, token_); }

void LocalFarm::stop() {
  for (ChildProcess& worker : workers_) worker.signal(SIGTERM);
  for (ChildProcess& worker : workers_) worker.stop(std::chrono::seconds(30));
  workers_.clear();
  if (scheduler_) scheduler_->shutdown();
}

}  // namespace pathfarm::farm
