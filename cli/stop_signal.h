#pragma once
// SIGTERM and SIGINT ask a long-running command (scheduler, worker, local) to finish
// cleanly instead of killing it.
#include <atomic>

namespace pathfarm {

// Installs the handlers (once) and returns the flag they set.
const std::atomic<bool>& stopRequested();

}  // namespace pathfarm
