#include "scheduler/worker_sessions.h"

#include "proto/wire/connection.h"
#include "proto/wire/sha256.h"

namespace pathfarm::farm {

NewSession WorkerSessions::make() {
  NewSession session;
  session.key = randomToken();
  session.hash = sha256Hex(session.key);
  return session;
}

void WorkerSessions::remember(int64_t workerId, const std::string& hash) {
  const std::lock_guard lock(mutex_);
  hashes_[workerId] = hash;
}

std::optional<int64_t> WorkerSessions::workerOf(const grpc::ServerContext& context) {
  const auto session = sessionOf(context);
  if (!session) return std::nullopt;
  const std::string hash = sha256Hex(session->key);
  {
    const std::lock_guard lock(mutex_);
    // Both are digests of secrets: comparing them reveals nothing of a key.
    if (const auto it = hashes_.find(session->workerId); it != hashes_.end())
      return it->second == hash ? std::optional(session->workerId) : std::nullopt;
  }
  if (!state_.sessionMatches(session->workerId, hash)) return std::nullopt;
  remember(session->workerId, hash);
  return session->workerId;
}

}  // namespace pathfarm::farm
