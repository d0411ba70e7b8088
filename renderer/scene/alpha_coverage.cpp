#include "renderer/scene/alpha_coverage.h"

#include <cmath>

namespace pathfarm {

AlphaCoverage::AlphaCoverage(Mode mode, float cutoff, float factor, int width, int height, std::vector<float> alpha)
    : mode_(mode), cutoff_(cutoff), factor_(factor), width_(width), height_(height), alpha_(std::move(alpha)) {}

float AlphaCoverage::alphaAt(Vec2f uv) const {
  if (alpha_.empty()) return factor_;
  // Nearest texel with repeat wrapping: the cutoff test is a threshold, so bilinear
  // weights would only move the edge by a fraction of a texel.
  const auto index = [](float t, int size) {
    if (!std::isfinite(t)) return 0;
    const float f = t - std::floor(t);
    return std::min(size - 1, static_cast<int>(f * static_cast<float>(size)));
  };
  const int x = index(uv.x, width_), y = height_ - 1 - index(uv.y, height_);
  return factor_ * alpha_[static_cast<size_t>(y) * static_cast<size_t>(width_) + static_cast<size_t>(x)];
}

bool AlphaCoverage::covers(Vec2f uv, float random) const {
  const float alpha = alphaAt(uv);
  return mode_ == Mode::Mask ? alpha >= cutoff_ : random < alpha;
}

float hashToUnit(uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
  uint32_t h = a * 0x9E3779B9u ^ b * 0x85EBCA6Bu ^ c * 0xC2B2AE35u ^ d * 0x27D4EB2Fu;
  h ^= h >> 16;
  h *= 0x7FEB352Du;
  h ^= h >> 15;
  h *= 0x846CA68Bu;
  h ^= h >> 16;
  return static_cast<float>(h >> 8) * 0x1p-24f;
}

}  // namespace pathfarm
