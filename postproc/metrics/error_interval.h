#pragma once
// 95 % intervals of error figures, by a percentile bootstrap over blocks of pixels
// (error_terms.h): the blocks are drawn with replacement, the figure recomputed, and the
// 2.5th and 97.5th percentiles of the recomputed figures bound it. The reference's noise
// is in every term, so its share of the uncertainty is in the interval too. The resampling
// is seeded: the same terms give the same interval.
#include <limits>

#include "postproc/metrics/error_terms.h"

namespace pathfarm {

struct Interval {
  double estimate = 0;
  double low = 0, high = 0;
  bool contains(double value) const { return low <= value && value <= high; }
};

// The mean term (an error against the truth) and its interval; unbounded with fewer than
// two blocks, where the spread between blocks says nothing.
Interval meanInterval(const BlockedTerms& terms);

// The highest of several means (the worst tile's error) and its interval. Each resample
// redraws every tile's blocks and takes the highest mean again, so the interval carries
// the choice of the worst among noisy candidates, not only that tile's own noise. Throws
// std::invalid_argument without a tile.
Interval maxOfMeansInterval(const std::vector<BlockedTerms>& tiles);

// The ratio of two means over the same blocks, resampled together (a pipeline's error
// over plain pt's, measured on the same frames). When the denominator's mean can reach 0
// within its uncertainty the ratio is not bounded: high is infinity (and low too when the
// denominator's estimate itself is not above 0). Throws std::invalid_argument for terms
// over different blocks.
Interval ratioInterval(const BlockedTerms& numerator, const BlockedTerms& denominator);

}  // namespace pathfarm
