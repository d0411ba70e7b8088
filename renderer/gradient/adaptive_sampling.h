#pragma once
// Adaptive sampling of gradient-domain renders (Manzi et al. 2016, Section 4.3): after a
// uniform first batch, each later batch gives pixels samples in proportion to the
// relative variance of their spatial differences, median-filtered (5x5) against
// outliers, smoothed with the separable kernel [0.1 0.2 0.4 0.2 0.1] and clamped to
// 8 times its mean.
#include <cstdint>
#include <vector>

namespace pathfarm {

// The smoothed, clamped density from per-pixel relative variances (non-finite count as 0).
std::vector<float> samplingDensity(const std::vector<float>& relativeVariance, int width, int height);

// Samples per pixel for a batch of about `budget` samples, in proportion to `density`
// (uniform where it is zero everywhere). Deterministic: rounding carries the fractional
// remainder along scanline order, so the counts add up to the budget.
std::vector<uint32_t> allocateSamples(const std::vector<float>& density, uint64_t budget);

}  // namespace pathfarm
