#pragma once
// The temporal proposal of Van de Woestijne et al. 2017: a new time tau' drawn from a
// piecewise-constant density on [tau - D, tau + D] (cut to the window) that puts a fixed
// share of its mass on the parts where the shutter is closed and the rest on the open
// parts, each share uniform over its parts. Both the sample and the density are exact,
// so a Metropolis acceptance can use the reverse density T(tau' -> tau).
#include "renderer/metropolis/window_time.h"

namespace pathfarm {

class TemporalProposal {
 public:
  // The share of proposals landing where the shutter is closed, when the interval has
  // both kinds of time.
  static constexpr double kClosedShare = 0.1;

  // Throws std::invalid_argument unless delta (in frames) is positive and finite.
  TemporalProposal(const WindowTime& time, double delta);

  double delta() const { return delta_; }
  // tau' for a uniform u in [0, 1); tau must lie in the window.
  double sample(double tau, double u) const;
  // The density (per frame of time) of proposing tauNext from tau.
  double density(double tau, double tauNext) const;
  // The probability that a proposal from tau lands where the shutter is closed.
  double closedMass(double tau) const;

 private:
  struct Interval {
    double lo, hi;          // [tau - D, tau + D] cut to the window
    double open, closed;    // the lengths of its open and closed parts
  };
  Interval intervalAround(double tau) const;
  static double closedShareOf(const Interval& interval);

  const WindowTime& time_;
  double delta_;
};

}  // namespace pathfarm
