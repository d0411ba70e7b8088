#include "postproc/metrics/error_interval.h"

#include <algorithm>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <tuple>

namespace pathfarm {
namespace {

constexpr int kResamples = 2000;
constexpr uint64_t kSeed = 0x9e3779b97f4a7c15ull;

// The 2.5th and 97.5th percentiles of `values` (sorted in place).
std::pair<double, double> percentiles(std::vector<double>& values) {
  std::sort(values.begin(), values.end());
  const auto at = [&](double q) { return values[static_cast<size_t>(q * static_cast<double>(values.size() - 1))]; };
  return {at(0.025), at(0.975)};
}

// Calls visit(b) for the blocks of one resample: as many as there are, drawn with replacement.
template <class Visit>
void resample(std::mt19937_64& random, size_t blocks, Visit visit) {
  std::uniform_int_distribution<size_t> pick(0, blocks - 1);
  for (size_t i = 0; i < blocks; ++i) visit(pick(random));
}

}  // namespace

Interval meanInterval(const BlockedTerms& terms) {
  Interval interval;
  interval.estimate = interval.low = interval.high = terms.mean();
  if (terms.sums.size() < 2) return interval;
  std::mt19937_64 random(kSeed);
  std::vector<double> means(kResamples);
  for (double& mean : means) {
    double sum = 0, count = 0;
    resample(random, terms.sums.size(), [&](size_t b) {
      sum += terms.sums[b];
      count += terms.counts[b];
    });
    mean = sum / count;
  }
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
  std::mt19937_64 random(kSeed);
  std::vector<double> ratios(kResamples);
  for (double& ratio : ratios) {
    double above = 0, under = 0;
    resample(random, numerator.sums.size(), [&](size_t b) {
      above += numerator.sums[b];
      under += denominator.sums[b];
    });
    ratio = under > 0 ? above / under : kInfinity;
  }
  std::tie(interval.low, interval.high) = percentiles(ratios);
  return interval;
}

}  // namespace pathfarm
