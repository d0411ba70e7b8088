#include "renderer/metropolis/temporal_proposal.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pathfarm {

TemporalProposal::TemporalProposal(const WindowTime& time, double delta) : time_(time), delta_(delta) {
  if (!(delta > 0) || !std::isfinite(delta))
    throw std::invalid_argument("the temporal perturbation's reach D must be a positive number of frames");
}

TemporalProposal::Interval TemporalProposal::intervalAround(double tau) const {
  Interval interval;
  interval.lo = std::max(tau - delta_, time_.begin());
  interval.hi = std::min(tau + delta_, time_.end());
  interval.open = std::max(0.0, time_.openBefore(interval.hi) - time_.openBefore(interval.lo));
  interval.closed = std::max(0.0, (interval.hi - interval.lo) - interval.open);
  return interval;
}

// All the mass goes to one kind of time when the interval holds none of the other.
double TemporalProposal::closedShareOf(const Interval& interval) {
  if (interval.closed <= 0) return 0;
  if (interval.open <= 0) return 1;
  return kClosedShare;
}

double TemporalProposal::sample(double tau, double u) const {
  const Interval interval = intervalAround(tau);
  const double closedShare = closedShareOf(interval);
  if (u < closedShare) {
    const double v = u / closedShare;
    return std::clamp(time_.atClosedMeasure(time_.closedBefore(interval.lo) + v * interval.closed), interval.lo,
                      std::nextafter(interval.hi, interval.lo));
  }
  const double v = (u - closedShare) / (1 - closedShare);
  return std::clamp(time_.atOpenMeasure(time_.openBefore(interval.lo) + v * interval.open), interval.lo,
                    std::nextafter(interval.hi, interval.lo));
}

double TemporalProposal::density(double tau, double tauNext) const {
  if (!time_.contains(tau) || !time_.contains(tauNext) || std::abs(tauNext - tau) > delta_) return 0;
  const Interval interval = intervalAround(tau);
  const double closedShare = closedShareOf(interval);
  if (time_.isOpen(tauNext)) return interval.open > 0 ? (1 - closedShare) / interval.open : 0;
  return interval.closed > 0 ? closedShare / interval.closed : 0;
}

double TemporalProposal::closedMass(double tau) const { return closedShareOf(intervalAround(tau)); }

}  // namespace pathfarm
