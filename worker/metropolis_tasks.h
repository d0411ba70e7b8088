#pragma once
// The Metropolis pipelines' tasks (pssmlt, mlt, tmlt; scheduler/planner.h) on top of the
// renderer's MetropolisRenderer (renderer/metropolis/metropolis_renderer.h):
//   mlt_seed_pool  the window's bootstrap: a 1x1 chunk whose attribute
//                  "pathfarm.mlt.seed_pool" holds the pool as text;
//   mlt_chains     the chain blocks [block_first, block_first + block_count) of the window,
//                  every block kept apart (channels "<frame index>.<block>.R/G/B", the block's
//                  statistics in "pathfarm.mlt.block.<block>"), since the merge must sum the
//                  blocks themselves to give the same bits for any split into tasks;
//   mlt_merge      one frame of the window from every block of every chain task.
#include <atomic>
#include <vector>

#include "renderer/metropolis/metropolis_renderer.h"
#include "worker/filter_tasks.h"

namespace pathfarm::farm {

// The renderer's settings for a Metropolis shot, running on `threads` threads (0: all).
MetropolisSettings metropolisSettingsOf(const ShotSpec& spec, int threads);

TaskOutput runSeedPoolTask(const MetropolisRenderer& renderer, const Lease& lease);
// `progress` is called with the fraction of the task's chains done; it may throw to stop.
TaskOutput runChainsTask(const MetropolisRenderer& renderer, const Lease& lease, const std::vector<TaskInput>& inputs,
                         const std::function<void(double)>& progress);
TaskOutput runMergeTask(const MetropolisRenderer& renderer, const Lease& lease, const std::vector<TaskInput>& inputs);

}  // namespace pathfarm::farm
