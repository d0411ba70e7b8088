#pragma once
// Sums computed in parallel with the same bits for any thread count: the range is cut
// into chunks of a fixed size, each chunk sums on its own, and the chunks' sums are
// added in chunk order.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <vector>

namespace pathfarm {

// Runs body(begin, end) -> std::array<double, K> over [0, n) in chunks of `chunk` and
// returns the chunks' results summed in chunk order.
template <size_t K, class Body>
std::array<double, K> chunkedSum(size_t n, size_t chunk, Body body) {
  std::vector<std::array<double, K>> partial((n + chunk - 1) / chunk);
  tbb::parallel_for(size_t{0}, partial.size(),
                    [&](size_t c) { partial[c] = body(c * chunk, std::min(n, (c + 1) * chunk)); });
  std::array<double, K> total{};
  for (const auto& p : partial)
    for (size_t k = 0; k < K; ++k) total[k] += p[k];
  return total;
}

// Per color channel, for vectors interleaved R, G, B.
using ChannelSums = std::array<double, 3>;

}  // namespace pathfarm
