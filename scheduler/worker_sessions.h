#pragma once
// Which worker a call comes from. Register hands a worker a random session key; every
// later call carries the worker id with it, checked against the key's hash in the
// database (so sessions outlive a scheduler restart) and remembered after the first check.
#include <grpcpp/grpcpp.h>

#include <map>
#include <mutex>
#include <optional>
#include <string>

#include "scheduler/farm_state.h"

namespace pathfarm::farm {

struct NewSession {
  std::string key;   // for the worker
  std::string hash;  // for the database
};

class WorkerSessions {
 public:
  explicit WorkerSessions(FarmState& state) : state_(state) {}

  static NewSession make();
  void remember(int64_t workerId, const std::string& hash);
  // The worker the call's session names, if its key is that worker's.
  std::optional<int64_t> workerOf(const grpc::ServerContext& context);

 private:
  FarmState& state_;
  std::mutex mutex_;
  std::map<int64_t, std::string> hashes_;  // checked sessions
};

}  // namespace pathfarm::farm
