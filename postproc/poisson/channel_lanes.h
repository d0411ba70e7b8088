#pragma once
// Loops over vectors interleaved R, G, B that the compiler vectorizes: they run over 12
// values (4 pixels) at a time, lane k holding channel k mod 3, so per-channel scalars
// and per-channel sums become 12-wide arrays without a reordering of any sum.
#include <array>
#include <cstddef>

#include "postproc/poisson/chunked_sum.h"

namespace pathfarm {

using Lanes = std::array<float, 12>;

// A per-channel scalar repeated for the 12 lanes.
inline Lanes lanesOf(const std::array<float, 3>& perChannel) {
  Lanes out{};
  for (size_t k = 0; k < out.size(); ++k) out[k] = perChannel[k % 3];
  return out;
}

// Runs body(i, k) for the values i of pixels [begin, end), k = (i - 3 begin) mod 12.
template <class Body>
void forValues(size_t begin, size_t end, Body body) {
  size_t i = 3 * begin;
  for (; i + 12 <= 3 * end; i += 12)
    for (size_t k = 0; k < 12; ++k) body(i + k, k);
  for (size_t k = 0; i < 3 * end; ++i, ++k) body(i, k);
}

// Per channel, the sums of 12 lanes, added in lane order.
inline ChannelSums channelsOf(const std::array<double, 12>& lanes) {
  ChannelSums sums{};
  for (size_t k = 0; k < lanes.size(); ++k) sums[k % 3] += lanes[k];
  return sums;
}

// Per channel, the sum of a[i] * b[i] over the values of pixels [begin, end).
inline ChannelSums channelDot(const float* a, const float* b, size_t begin, size_t end) {
  std::array<double, 12> lanes{};
  forValues(begin, end, [&](size_t i, size_t k) { lanes[k] += static_cast<double>(a[i]) * b[i]; });
  return channelsOf(lanes);
}

}  // namespace pathfarm
