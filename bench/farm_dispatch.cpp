// Dispatch throughput of the farm: no-op tasks through a real scheduler (SQLite, gRPC on
// loopback) and worker clients, each its own gRPC channel, as a separate process would.
//
//   build/bin/farm_dispatch [--workers 8] [--tasks 20000] [--repeat 3]
//
// Prints, as medians over the repeats: tasks per second from submission to the shot's
// end, and the median lease-to-complete latency of a task as the scheduler recorded it.
#include <spdlog/spdlog.h>
#include <sqlite3.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <thread>
#include <vector>

#include "bench/command_line.h"
#include "bench/median.h"
#include "client/farm_client.h"
#include "client/local_farm.h"
#include "scheduler/scheduler_server.h"
#include "worker/worker.h"

namespace {

using namespace pathfarm::farm;
using pathfarm::bench::median;

std::vector<double> leaseToCompleteSeconds(const std::filesystem::path& database) {
  sqlite3* db = nullptr;
  sqlite3_open_v2(database.c_str(), &db, SQLITE_OPEN_READONLY, nullptr);
  sqlite3_stmt* statement = nullptr;
  sqlite3_prepare_v2(db, "SELECT finished_at - leased_at FROM attempts WHERE state = 1", -1, &statement, nullptr);
  std::vector<double> latencies;
  while (sqlite3_step(statement) == SQLITE_ROW) latencies.push_back(sqlite3_column_double(statement, 0));
  sqlite3_finalize(statement);
  sqlite3_close(db);
  return latencies;
}

}  // namespace

int main(int argc, char** argv) {
  pathfarm::bench::CommandLine app("pathfarm dispatch throughput benchmark");
  int workers = 8, tasks = 20000, repeat = 3;
  app.option("--workers", workers);
  app.option("--tasks", tasks);
  app.option("--repeat", repeat);
  if (const auto exit = app.parse(argc, argv)) return *exit;
  spdlog::set_level(spdlog::level::warn);

  std::vector<double> throughput, latency;
  for (int r = 0; r < repeat; ++r) {
    const auto folder = std::filesystem::temp_directory_path() / "pathfarm_dispatch_bench";
    std::filesystem::remove_all(folder);
    SchedulerOptions options;
    options.listen = "127.0.0.1:0";
    options.database = folder / "farm.db";
    options.store = folder / "chunks";
    options.token = randomToken();
    std::filesystem::create_directories(folder);
    SchedulerServer scheduler(options);

    std::atomic<bool> stop{false};
    std::vector<std::thread> pool;
    for (int w = 0; w < workers; ++w) {
      pool.emplace_back([&, w] {
        WorkerOptions worker;
        worker.scheduler = scheduler.address();
        worker.threads = 1;
        worker.name = "bench-" + std::to_string(w);
        worker.token = options.token;
        worker.cache = folder / "cache";
        Worker(std::move(worker)).run(stop);
      });
    }
    FarmClient client(scheduler.address(), options.token);
    ShotSpec spec;
    spec.set_name("dispatch");
    spec.set_pipeline(PIPELINE_NOOP);
    spec.set_noop_tasks(tasks);
    const auto start = std::chrono::steady_clock::now();
    const int64_t id = client.submit(spec);
    const ShotSummary end = client.watch(id, [](const ShotSummary&) {});
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    stop = true;
    for (std::thread& t : pool) t.join();
    scheduler.shutdown();
    if (end.state() != SHOT_DONE) {
      std::fprintf(stderr, "the shot ended %s\n", ShotState_Name(end.state()).c_str());
      return 1;
    }
    throughput.push_back(tasks / seconds);
    latency.push_back(median(leaseToCompleteSeconds(options.database)));
    std::filesystem::remove_all(folder);
  }
  std::printf("%d no-op tasks, %d workers, %d repeats (medians)\n", tasks, workers, repeat);
  std::printf("dispatch: %.0f tasks/s\n", median(throughput));
  std::printf("lease-to-complete latency: %.3f ms\n", median(latency) * 1e3);
  return 0;
}
