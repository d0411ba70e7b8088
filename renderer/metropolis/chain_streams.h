#pragma once
// Where a Metropolis render's random numbers come from. Each bootstrap sample, each
// chain's seed choice and each chain has its own stream keyed by (scene seed, window,
// role, index), so any process can regenerate any of them, and a block of chains gives
// the same bits wherever and with however many threads it runs.
#include <cstdint>

#include "renderer/metropolis/window_time.h"
#include "renderer/sampling/sample_stream.h"

namespace pathfarm {

// The uniform numbers of bootstrap sample `index` (strategy `strategy` of `strategies`).
SampleStream bootstrapStream(uint64_t sceneSeed, FrameWindow window, uint64_t index, int strategy, int strategies);
// The number that picks chain `chain`'s seed from the pool.
SampleStream seedChoiceStream(uint64_t sceneSeed, FrameWindow window, uint32_t chain);
// Everything chain `chain` draws while it runs.
SampleStream chainStream(uint64_t sceneSeed, FrameWindow window, uint32_t chain);

}  // namespace pathfarm
