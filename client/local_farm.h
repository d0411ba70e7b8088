#pragma once
// A whole farm on this machine: a scheduler on an ephemeral loopback port with its
// database and chunk store in one folder, and N worker processes, guarded by a random
// access token. `pathfarm local` and the benchmarks use it; it stops everything it
// started when it goes out of scope.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "proto/wire/connection.h"
#include "client/child_process.h"
#include "client/farm_client.h"
#include "scheduler/scheduler_server.h"

namespace pathfarm::farm {

struct LocalFarmOptions {
  std::filesystem::path folder;  // farm.db, chunks/, logs/
  int workers = 2;
  int threadsPerWorker = 0;      // 0: the cores shared out among the workers
  std::string executable;        // the pathfarm binary the workers run
  FarmSettings farm;
  ShotLimits limits;             // what one submitted shot may ask for
  std::string http;              // HOST:PORT for the dashboard and /metrics; empty: none
};

class LocalFarm {
 public:
  explicit LocalFarm(LocalFarmOptions options);
  ~LocalFarm();

  FarmClient client() const;
  const std::string& address() const { return address_; }
  // Asks the workers to finish and stop, then stops the scheduler.
  void stop();

 private:
  LocalFarmOptions options_;
  std::string token_;
  std::unique_ptr<SchedulerServer> scheduler_;
  std::string address_;
  std::vector<ChildProcess> workers_;
};

}  // namespace pathfarm::farm
