#pragma once
// The median of a benchmark's repeated measurements (the upper one of an even count).
#include <algorithm>
#include <vector>

namespace pathfarm::bench {

inline double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

}  // namespace pathfarm::bench
