#include "renderer/metropolis/pssmlt/primary_samples.h"

#include <cmath>

namespace pathfarm {
namespace {

// The largest double below 1: keeps wrapped values in [0, 1).
constexpr double kBelowOne = 1 - 0x1p-53;

double uniformOf(SampleStream& random) { return random.next1D(); }

double wrap(double v) { return std::min(v - std::floor(v), kBelowOne); }

// A standard normal number (Box-Muller).
double normalOf(SampleStream& random) {
  const double u1 = 1 - uniformOf(random);  // in (0, 1]
  const double u2 = uniformOf(random);
  return std::sqrt(-2 * std::log(u1)) * std::cos(2 * M_PI * u2);
}

}  // namespace

PrimarySamples PrimarySamples::nextStep(bool large) const {
  PrimarySamples next = *this;
  ++next.step_;
  if (large) next.lastLargeStep_ = next.step_;
  return next;
}

PrimarySamples::Coordinate& PrimarySamples::at(int stream, size_t index) {
  std::vector<Coordinate>& coordinates = streams_[static_cast<size_t>(stream)];
  if (index >= coordinates.size()) coordinates.resize(index + 1);
  return coordinates[index];
}

double PrimarySamples::get(int stream, size_t index, SampleStream& random) {
  Coordinate& c = at(stream, index);
  if (c.lastModified < lastLargeStep_) {
    c.value = uniformOf(random);
    c.lastModified = lastLargeStep_;
  }
  const int64_t pending = step_ - c.lastModified;
  if (pending > 0) {
    c.value = wrap(c.value + normalOf(random) * kSmallStepSigma * std::sqrt(static_cast<double>(pending)));
    c.lastModified = step_;
  }
  return c.value;
}

void PrimarySamples::set(int stream, size_t index, double value, SampleStream& random) {
  get(stream, index, random);
  Coordinate& c = at(stream, index);
  c.value = wrap(value);
  c.lastModified = step_;
}

}  // namespace pathfarm
