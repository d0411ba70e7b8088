#include "renderer/metropolis/seed_choice.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

#include "renderer/metropolis/chain_streams.h"

namespace pathfarm {

SeedPool chooseSeeds(FrameWindow window, uint64_t sceneSeed, int strategies, const std::vector<double>& scalars,
                     int chains) {
  SeedPool pool;
  pool.window = window;
  pool.bootstrapSamples = scalars.size() / static_cast<size_t>(strategies);
  std::vector<double> cdf(scalars.size());
  double sum = 0;
  for (size_t i = 0; i < scalars.size(); ++i) {
    if (std::isfinite(scalars[i]) && scalars[i] > 0) sum += scalars[i];
    cdf[i] = sum;
  }
  if (!(sum > 0) || !std::isfinite(sum)) {
    spdlog::warn("Metropolis bootstrap of frames {}..{}: none of {} samples carried light to the camera; the frames "
                 "stay black",
                 window.first, window.end() - 1, pool.bootstrapSamples);
    return pool;
  }
  pool.normalization = sum / static_cast<double>(pool.bootstrapSamples);
  for (int c = 0; c < chains; ++c) {
    SampleStream random = seedChoiceStream(sceneSeed, window, static_cast<uint32_t>(c));
    // 64 random bits, so that pools of millions of samples are chosen from finely.
    const double u = std::min((random.nextUint() * 0x1p-32 + random.nextUint() * 0x1p-64) * sum,
                              std::nextafter(sum, 0.0));
    // The first sample whose cumulative sum exceeds u: never one of no contribution.
    const auto chosen = static_cast<size_t>(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin());
    pool.seeds.push_back({chosen / static_cast<size_t>(strategies), static_cast<int>(chosen % static_cast<size_t>(strategies)),
                          scalars[chosen]});
  }
  return pool;
}

}  // namespace pathfarm
