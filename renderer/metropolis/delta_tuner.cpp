#include "renderer/metropolis/delta_tuner.h"

#include <algorithm>
#include <cmath>

namespace pathfarm {

namespace {
constexpr double kMinDelta = 1e-3;
}

DeltaTuner::DeltaTuner(double initialDelta, double windowLength, bool enabled, double target, uint64_t tuningMutations)
    : delta_(initialDelta), maxDelta_(std::max(windowLength, kMinDelta)), target_(target), enabled_(enabled),
      tuningMutations_(tuningMutations) {}

void DeltaTuner::observe(uint64_t mutation, double acceptance) {
  if (!tuning(mutation)) return;
  ++observed_;
  const double step = (acceptance - target_) / std::sqrt(static_cast<double>(observed_));
  delta_ = std::clamp(delta_ * std::exp(step), kMinDelta, maxDelta_);
}

}  // namespace pathfarm
