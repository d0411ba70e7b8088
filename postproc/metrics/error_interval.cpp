#include "postproc/metrics/error_interval.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <tuple>

namespace pathfarm {
namespace {

constexpr int kResamples = 2000;
constexpr uint64_t kSeed = 0x9e3779b97f4a7c15ull;

// The 2.5th and 97.5th percentiles of `values` (sorted in place); a resample that gave no
// number (NaN) counts as unbounded.
std::pair<double, double> percentiles(std::vector<double>& values) {
  for (double& value : values)
    if (std::isnan(value)) value = std::numeric_limits<double>::infinity();
  std::sort(values.begin(), values.end());
  const auto at = [&](double q) { return values[static_cast<size_t>(q * static_cast<double>(values.size() - 1))]; };
  return {at(0.025), at(0.975)};
}

// Per resample (kResamples of them, as many blocks drawn with replacement as there are),
// the sums of `a` and of `b` over the drawn blocks: the same draws for both.
std::vector<std::pair<double, double>> resampledSums(const std::vector<double>& a, const std::vector<double>& b) {
  std::mt19937_64 random(kSeed);
  std::uniform_int_distribution<size_t> pick(0, a.size() - 1);
  std::vector<std::pair<double, double>> sums(kResamples);
  for (auto& [sumA, sumB] : sums)
    for (size_t i = 0; i < a.size(); ++i) {
      const size_t block = pick(random);
      sumA += a[block];
      sumB += b[block];
    }
  return sums;
}

}  // namespace

Interval meanInterval(const BlockedTerms& terms) {
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  Interval interval{terms.mean(), -kInfinity, kInfinity};
  if (terms.sums.size() < 2) return interval;
  std::vector<double> means;
  for (const auto& [sum, count] : resampledSums(terms.sums, terms.counts)) means.push_back(sum / count);
  std::tie(interval.low, interval.high) = percentiles(means);
  return interval;
}

Interval ratioInterval(const BlockedTerms& numerator, const BlockedTerms& denominator) {
  if (numerator.counts != denominator.counts)
    throw std::invalid_argument("a ratio of errors needs both measured over the same blocks");
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  Interval interval;
  const double below = denominator.mean();
  interval.estimate = below > 0 ? numerator.mean() / below : kInfinity;
  interval.low = below > 0 ? interval.estimate : -kInfinity;
  interval.high = kInfinity;
  if (!(below > 0) || numerator.sums.size() < 2) return interval;
  std::vector<double> ratios;
  for (const auto& [above, under] : resampledSums(numerator.sums, denominator.sums))
    ratios.push_back(under > 0 ? above / under : kInfinity);
  std::tie(interval.low, interval.high) = percentiles(ratios);
  return interval;
}

Interval maxOfMeansInterval(const std::vector<BlockedTerms>& tiles) {
  if (tiles.empty()) throw std::invalid_argument("the worst of no tile");
  Interval interval;
  interval.estimate = -std::numeric_limits<double>::infinity();
  for (const BlockedTerms& tile : tiles) interval.estimate = std::max(interval.estimate, tile.mean());
  std::mt19937_64 random(kSeed);
  std::vector<double> maxima(kResamples, -std::numeric_limits<double>::infinity());
  for (double& maximum : maxima)
    for (const BlockedTerms& tile : tiles) {
      std::uniform_int_distribution<size_t> pick(0, tile.sums.size() - 1);
      double sum = 0, count = 0;
      for (size_t i = 0; i < tile.sums.size(); ++i) {
        const size_t block = pick(random);
        sum += tile.sums[block];
        count += tile.counts[block];
      }
      maximum = std::max(maximum, sum / count);
    }
  std::tie(interval.low, interval.high) = percentiles(maxima);
  return interval;
}

}  // namespace pathfarm
