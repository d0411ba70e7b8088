#include "renderer/metropolis/chain_settings.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pathfarm {

void ChainSettings::validate() const {
  if (width <= 0 || height <= 0) throw std::invalid_argument("the image needs a positive size");
  if (!(mutationsPerPixel > 0) || !std::isfinite(mutationsPerPixel))
    throw std::invalid_argument("mutations per pixel must be positive");
  if (bootstrapSamples == 0u) throw std::invalid_argument("the bootstrap needs at least one sample");
  if (chains <= 0) throw std::invalid_argument("at least one Markov chain is needed");
  if (chainsPerBlock <= 0) throw std::invalid_argument("a block needs at least one chain");
  if (!(temporalDelta > 0) || !std::isfinite(temporalDelta))
    throw std::invalid_argument("the temporal reach D must be a positive number of frames");
  if (!(targetTemporalAcceptance > 0 && targetTemporalAcceptance < 1))
    throw std::invalid_argument("the target temporal acceptance must lie in (0, 1)");
  if (!(tuningShare >= 0 && tuningShare <= 1)) throw std::invalid_argument("the tuning share must lie in [0, 1]");
}

uint64_t ChainSettings::totalMutations(FrameWindow window) const {
  const double pixels = static_cast<double>(width) * height * window.count;
  return static_cast<uint64_t>(std::llround(mutationsPerPixel * pixels));
}

uint64_t ChainSettings::mutationsOfChain(FrameWindow window, int chain) const {
  const uint64_t total = totalMutations(window), n = static_cast<uint64_t>(chains);
  return total / n + (static_cast<uint64_t>(chain) < total % n ? 1 : 0);
}

uint64_t ChainSettings::bootstrapSamplesOf(FrameWindow window) const {
  if (bootstrapSamples) return *bootstrapSamples;
  return std::max(kMinimumBootstrapSamples, totalMutations(window) / kMutationsPerBootstrapSample);
}

double ChainSettings::filmScale(FrameWindow window, double normalization) const {
  const double pixels = static_cast<double>(width) * height * window.count;
  return normalization * pixels / static_cast<double>(totalMutations(window));
}

}  // namespace pathfarm
