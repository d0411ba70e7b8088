// Worker identity: which worker a session key names, and which worker an attempt is for.
#include <openssl/crypto.h>

#include "scheduler/farm_state_internal.h"

namespace pathfarm::farm {

bool FarmState::sessionMatches(int64_t workerId, const std::string& sessionHash) {
  return transact([&]() -> bool {
    Statement& q = db_.query("SELECT session_hash FROM workers WHERE id = ?1").bind(1, workerId);
    const std::string stored = q.step() ? q.text(0) : "";
    q.reset();
    // Compared in constant time; a worker registered without a session has none to match.
    return !stored.empty() && stored.size() == sessionHash.size() &&
           CRYPTO_memcmp(stored.data(), sessionHash.data(), stored.size()) == 0;
  });
}

std::optional<int64_t> FarmState::attemptWorker(int64_t attemptId) {
  return transact([&]() -> std::optional<int64_t> {
    Statement& q = db_.query("SELECT worker_id FROM attempts WHERE id = ?1").bind(1, attemptId);
    std::optional<int64_t> worker;
    if (q.step()) worker = q.integer(0);
    q.reset();
    return worker;
  });
}

}  // namespace pathfarm::farm
