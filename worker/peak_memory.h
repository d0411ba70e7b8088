#pragma once
// The largest resident memory of the worker process (Linux's VmHWM), and a way to start
// counting it again: what a task needed at most, measured on a worker with one slot.
#include <cstdint>
#include <optional>

namespace pathfarm::farm {

// Starts the peak over at the current resident memory (writes "5" to
// /proc/self/clear_refs); false where the kernel does not allow it.
bool restartPeakResident();
// The peak resident memory since the process started or since the last restart, in bytes;
// nothing where /proc/self/status does not say.
std::optional<uint64_t> peakResidentBytes();

}  // namespace pathfarm::farm
