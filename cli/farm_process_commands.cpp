// `pathfarm scheduler` and `pathfarm worker`: the farm's long-running processes.
#include <spdlog/spdlog.h>
#include <sys/prctl.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <fstream>
#include <memory>
#include <thread>

#include "cli/command.h"
#include "cli/shot_size_options.h"
#include "cli/stop_signal.h"
#include "cli/tls_options.h"
#include "proto/wire/connection.h"
#include "scheduler/scheduler_server.h"
#include "worker/worker.h"

namespace pathfarm {
namespace {

struct SchedulerArguments {
  farm::SchedulerOptions options;
  std::string tokenFile;
  std::string workerTokenFile;
  std::string portFile;
  std::string httpPortFile;
  double retainDays = 0;
};

int runScheduler(SchedulerArguments& arguments) {
  const auto& stop = stopRequested();
  try {
    arguments.options.token = farm::loadToken(arguments.tokenFile);
    if (!arguments.workerTokenFile.empty()) arguments.options.workerToken = farm::loadToken(arguments.workerTokenFile);
    arguments.options.farm.retainSeconds = arguments.retainDays * 86400;
    if (!arguments.options.workerToken.empty() && arguments.options.token.empty())
      throw std::runtime_error("--worker-token-file needs a client token too (--token-file or PATHFARM_TOKEN[_FILE])");
    farm::SchedulerServer server(arguments.options);
    // Written after the port is bound, renamed into place so a reader never sees half.
    const auto writePort = [](const std::string& file, int port) {
      if (file.empty()) return;
      const std::string partial = file + ".partial";
      std::ofstream(partial) << port << "\n";
      std::filesystem::rename(partial, file);
    };
    writePort(arguments.httpPortFile, server.httpPort());
    writePort(arguments.portFile, server.port());
    while (!stop) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    spdlog::info("scheduler stopping");
    server.shutdown();
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return kExitFailure;
  }
  return kExitOk;
}

struct WorkerArguments {
  farm::WorkerOptions options;
  std::string tokenFile;
  double cacheMaxGb = 20;
  double decodedInputsGb = static_cast<double>(farm::TaskRunner::kDefaultDecodedInputBytes) / 1e9;
  pid_t parent = 0;  // end when this process ends (0: never)
};

// The worker ends with its parent, even when the parent is SIGKILLed: the workers of a
// killed `pathfarm local` do not outlive it. At once (SIGKILL): the scheduler they would
// finish and deliver their tasks to ran inside that process, and a graceful stop waited a
// minute for it. Returns false when the parent is gone already.
bool endWithParent(pid_t parent) {
  if (parent == 0) return true;
  if (prctl(PR_SET_PDEATHSIG, SIGKILL) != 0) spdlog::warn("cannot follow the parent process: {}", std::strerror(errno));
  return getppid() == parent;
}

int runWorker(WorkerArguments& arguments) {
  const auto& stop = stopRequested();
  if (!endWithParent(arguments.parent)) {
    spdlog::error("the process that started this worker ({}) has ended", arguments.parent);
    return kExitFailure;
  }
  try {
    arguments.options.token = farm::loadToken(arguments.tokenFile);
    arguments.options.tls = farm::clientTlsFromEnvironment(arguments.options.tls);
    arguments.options.cacheMaxBytes = static_cast<uint64_t>(arguments.cacheMaxGb * 1e9);
    arguments.options.decodedInputMaxBytes = static_cast<uint64_t>(arguments.decodedInputsGb * 1e9);
    farm::Worker(arguments.options).run(stop);
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return kExitFailure;
  }
  return kExitOk;
}

}  // namespace

std::vector<Command> addFarmProcessCommands(CLI::App& app) {
  auto scheduler = std::make_shared<SchedulerArguments>();
  CLI::App* s = app.add_subcommand("scheduler", "run the farm's scheduler (state in SQLite, chunks on disk)");
  s->add_option("--listen", scheduler->options.listen, "address to serve on; loopback unless you say otherwise")
      ->capture_default_str();
  s->add_option("--db", scheduler->options.database, "SQLite database file")->capture_default_str();
  s->add_option("--store", scheduler->options.store, "folder of content-addressed chunks")->capture_default_str();
  s->add_option("--token-file", scheduler->tokenFile,
                "file holding the access token every call must carry (or PATHFARM_TOKEN[_FILE])");
  s->add_option("--worker-token-file", scheduler->workerTokenFile,
                "file holding the token workers carry instead: clients and workers then cannot act as each other");
  s->add_option("--lease-seconds", scheduler->options.farm.leaseSeconds, "lease lifetime without a heartbeat")
      ->check(CLI::Range(0.5, 3600.0))
      ->capture_default_str();
  s->add_option("--hung-seconds", scheduler->options.farm.hungSeconds, "a task without progress this long is retried")
      ->check(CLI::Range(1.0, 1e6))
      ->capture_default_str();
  s->add_option("--retry-backoff", scheduler->options.farm.retryBackoffSeconds, "first retry delay in seconds")
      ->check(CLI::Range(0.0, 3600.0))
      ->capture_default_str();
  addShotSizeOptions(s, scheduler->options.limits, scheduler->options.farm);
  s->add_option("--max-lost-workers", scheduler->options.farm.maxLostWorkers,
                "a task whose lease expires this often (its workers vanish) fails the shot; not charged to max_attempts")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  s->add_option("--retain-days", scheduler->retainDays,
                "delete shots finished this many days ago, with their chunks and records (0: keep everything)")
      ->check(CLI::Range(0.0, 36500.0))
      ->capture_default_str();
  s->add_option("--port-file", scheduler->portFile, "write the bound port here (for --listen HOST:0)");
  s->add_option("--http", scheduler->options.http,
                "HOST:PORT serving the dashboard at / and Prometheus metrics at /metrics (beyond loopback: a "
                "token, and TLS or --insecure; docs/dashboard.md)");
  s->add_option("--http-port-file", scheduler->httpPortFile, "write the bound HTTP port here (for --http HOST:0)");
  s->add_flag("--insecure", scheduler->options.insecure,
              "serve beyond loopback without TLS (the token and frames cross in clear)");
  s->add_option("--tls-cert", scheduler->options.tls.certFile, "PEM certificate: serve gRPC over TLS, HTTP as HTTPS");
  s->add_option("--tls-key", scheduler->options.tls.keyFile, "PEM private key of --tls-cert");
  s->add_option("--tls-client-ca", scheduler->options.tls.clientCaFile,
                "PEM CA: every client and worker must show a certificate it signed");

  auto worker = std::make_shared<WorkerArguments>();
  CLI::App* w = app.add_subcommand("worker", "run a worker that leases and renders tasks");
  w->add_option("--scheduler", worker->options.scheduler, "scheduler address HOST:PORT")->capture_default_str();
  w->add_option("--slots", worker->options.slots, "tasks at once")->check(CLI::Range(1, 256))->capture_default_str();
  w->add_option("--threads", worker->options.threads, "render threads per task (0: every core)")
      ->check(CLI::Range(0, 1024));
  w->add_option("--name", worker->options.name, "name shown by `pathfarm workers` (default host:pid)");
  w->add_option("--tags", worker->options.tags, "tags this worker offers, e.g. gpu,big: shots requiring them")
      ->delimiter(',');
  w->add_option("--cache", worker->options.cache, "folder caching input chunks and uploaded scenes");
  w->add_option("--cache-max-gb", worker->cacheMaxGb, "the cache is trimmed to this size, least recently used first")
      ->check(CLI::Range(0.001, 1e6))
      ->capture_default_str();
  w->add_option("--decoded-inputs-gb", worker->decodedInputsGb,
                "memory for input frames kept decoded between tasks (0: decode every time)")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  w->add_option("--token-file", worker->tokenFile, "file holding the farm's access token (or PATHFARM_TOKEN[_FILE])");
  addClientTlsOptions(w, worker->options.tls);
  w->add_option("--hand-back-after", worker->options.handBackAfterSeconds,
                "on SIGTERM: a task still running after this many seconds is handed back to the scheduler, which "
                "gives it to another worker at once (0: at once); one that ends sooner is delivered")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  w->add_option("--parent", worker->parent,
                "end, without finishing its tasks, when process PID ends (`pathfarm local` passes its own)");

  return {{s, [scheduler] { return runScheduler(*scheduler); }}, {w, [worker] { return runWorker(*worker); }}};
}

}  // namespace pathfarm
