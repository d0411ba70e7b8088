#pragma once
// The result of a window's bootstrap (Veach 1997, 11.3; Kelemen et al. 2002): the
// normalization b, the mean scalar contribution of independent samples over the window's
// open time, and each chain's seed, chosen among those samples in proportion to their
// contribution. A seed is named by small integers only; the process that runs the chain
// regenerates the sample from its bootstrap stream (chain_streams.h). The farm ships
// the pool between tasks as text.
#include <cstdint>
#include <string>
#include <vector>

#include "renderer/metropolis/window_time.h"

namespace pathfarm {

struct ChainSeed {
  uint64_t bootstrapIndex = 0;
  int strategy = 0;          // e.g. the path depth, for targets that seed by strategy
  double contribution = 0;   // its scalar contribution, checked when it is regenerated
};

struct SeedPool {
  FrameWindow window;
  uint64_t bootstrapSamples = 0;
  double normalization = 0;      // b; 0 when no sample carried light
  std::vector<ChainSeed> seeds;  // one per chain; empty when b is 0

  std::string serialize() const;
  // Throws std::invalid_argument naming what is wrong with the text.
  static SeedPool parse(const std::string& text);
};

}  // namespace pathfarm
