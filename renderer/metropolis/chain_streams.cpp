#include "renderer/metropolis/chain_streams.h"

#include <stdexcept>

namespace pathfarm {
namespace {

// Camera samples use x >= 0; negative x values name the Metropolis roles, and the
// window's length takes the y slot, so that windows starting at the same frame differ.
enum Role : int32_t { kBootstrap = -1, kSeedChoice = -2, kChain = -3 };

SampleStream streamOf(uint64_t sceneSeed, FrameWindow window, Role role, uint64_t index) {
  if (index > UINT32_MAX) throw std::invalid_argument("too many Metropolis samples for the stream keys (at most 2^32)");
  return SampleStream({sceneSeed, window.first, role, window.count, static_cast<uint32_t>(index)});
}

}  // namespace

SampleStream bootstrapStream(uint64_t sceneSeed, FrameWindow window, uint64_t index, int strategy, int strategies) {
  return streamOf(sceneSeed, window, kBootstrap, index * static_cast<uint64_t>(strategies) + static_cast<uint64_t>(strategy));
}

SampleStream seedChoiceStream(uint64_t sceneSeed, FrameWindow window, uint32_t chain) {
  return streamOf(sceneSeed, window, kSeedChoice, chain);
}

SampleStream chainStream(uint64_t sceneSeed, FrameWindow window, uint32_t chain) {
  return streamOf(sceneSeed, window, kChain, chain);
}

}  // namespace pathfarm
