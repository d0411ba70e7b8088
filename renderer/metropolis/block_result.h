#pragma once
// A block of Markov chains is the unit of work the farm hands out: a fixed range of
// chains of one window, whose result depends only on (scene, settings, seed pool, block).
// Blocks are merged by summing their frames in block order, so the merged frames are the
// same bits however the blocks were spread over tasks and processes.
#include <vector>

#include "image/frame_image.h"
#include "renderer/metropolis/mutation_stats.h"
#include "renderer/metropolis/window_time.h"

namespace pathfarm {

struct BlockResult {
  int block = 0;
  // Per frame of the window, this block's share of the radiance estimate (R, G, B).
  std::vector<FrameImage> frames;
  MutationStats stats;
};

// The sum of every block 0 .. blocks - 1, each given exactly once (in any order), with
// the summed statistics in each frame's attributes. Throws std::invalid_argument for a
// missing, repeated or foreign block.
std::vector<FrameImage> mergeBlocks(FrameWindow window, int blocks, std::vector<BlockResult> results);

}  // namespace pathfarm
