#include "cli/stop_signal.h"

#include <csignal>

namespace pathfarm {
namespace {

std::atomic<bool> requested{false};

extern "C" void onStopSignal(int) { requested = true; }

}  // namespace

const std::atomic<bool>& stopRequested() {
  static const bool installed = [] {
    struct sigaction action {};
    action.sa_handler = onStopSignal;
    sigemptyset(&action.sa_mask);
    sigaction(SIGTERM, &action, nullptr);
    sigaction(SIGINT, &action, nullptr);
    return true;
  }();
  (void)installed;
  return requested;
}

}  // namespace pathfarm
