#pragma once
// One of a worker's slots: leases a task, fetches its inputs (from the worker's cache or
// the scheduler), runs it while renewing the lease, and delivers its output and follow-up
// tiles; then the next, until told to stop. An unreachable scheduler is waited for; a
// finished result is kept and offered again until the lease is lost.
#include <atomic>

#include "proto/wire/chunk_store.h"
#include "worker/cache_trim.h"
#include "worker/scheduler_link.h"
#include "worker/task_runner.h"
#include "worker/worker.h"

namespace pathfarm::farm {

// Runs one slot until `stop` turns true; the tasks in hand are finished and delivered.
void runSlot(SchedulerLink& link, TaskRunner& runner, ChunkStore& cache, CacheBound& bound, const WorkerOptions& options,
             double heartbeatSeconds, const std::atomic<bool>& stop);

}  // namespace pathfarm::farm
