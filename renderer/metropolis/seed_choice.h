#pragma once
// From the bootstrap's scalar contributions to a seed pool: the normalization b is their
// mean per bootstrap sample (the strategies of a sample add up, as the estimates of one
// image do), and each chain picks its seed with probability proportional to contribution.
#include <cstdint>
#include <vector>

#include "renderer/metropolis/seed_pool.h"

namespace pathfarm {

// `scalars[i * strategies + s]` is bootstrap sample i's contribution with strategy s.
// Logs a warning and returns a pool without seeds when no sample carried light.
SeedPool chooseSeeds(FrameWindow window, uint64_t sceneSeed, int strategies, const std::vector<double>& scalars,
                     int chains);

}  // namespace pathfarm
