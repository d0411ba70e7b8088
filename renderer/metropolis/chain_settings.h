#pragma once
// The numbers that shape a window's Markov chains, whatever the state they move in.
#include <cstdint>
#include <optional>

#include "renderer/metropolis/window_time.h"

namespace pathfarm {

inline constexpr uint64_t kMinimumBootstrapSamples = 10000;
inline constexpr uint64_t kMutationsPerBootstrapSample = 256;

struct ChainSettings {
  uint64_t sceneSeed = 0;
  int width = 64, height = 64;
  double mutationsPerPixel = 64;  // per frame of the window
  // The bootstrap's samples per window; none: sized to the window (bootstrapSamplesOf).
  std::optional<uint64_t> bootstrapSamples;
  int chains = 64;
  int chainsPerBlock = 16;
  double temporalDelta = 1;       // D, in frames
  bool tuneDelta = false;
  double targetTemporalAcceptance = 0.23;
  double tuningShare = 0.1;       // the first part of each chain in which D is tuned
  int threads = 0;                // 0: every core

  // Throws std::invalid_argument naming the first setting out of range.
  void validate() const;
  int blocks() const { return (chains + chainsPerBlock - 1) / chainsPerBlock; }
  // Mutations of all chains of the window together, and of chain `chain`: the total
  // split as evenly as integers allow, the first chains taking the remainder.
  uint64_t totalMutations(FrameWindow window) const;
  uint64_t mutationsOfChain(FrameWindow window, int chain) const;
  // The bootstrap's samples for `window`: the count set, or one sample per
  // kMutationsPerBootstrapSample of the window's mutations and at least
  // kMinimumBootstrapSamples. The normalization's relative error then falls with the
  // window's budget as the chains' noise does (docs/metropolis.md, "How many samples").
  uint64_t bootstrapSamplesOf(FrameWindow window) const;
  // The splat films' scale that turns sums of value / scalar into radiance
  // (Kelemen et al. 2002): b times the pixels and frames over the number of mutations.
  double filmScale(FrameWindow window, double normalization) const;
};

}  // namespace pathfarm
