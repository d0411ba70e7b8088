#pragma once
// The state of primary-sample-space MLT (Kelemen et al. 2002): a vector of numbers in
// [0, 1) that a path sampler reads as its uniform numbers, in three streams (camera
// subpath, light subpath, connection) so that a coordinate keeps its meaning when the
// other subpath changes length (as in pbrt-v3's MLT sampler).
//
// Mutations are lazy: a proposal only records whether it is a large step (every
// coordinate fresh) or a small step (every coordinate perturbed), and a coordinate is
// brought up to date when the path reads it. A coordinate last touched n accepted steps
// ago, with no large step in between, receives the n pending small steps at once: the
// sum of n normal perturbations of deviation sigma is one of deviation sigma sqrt(n).
// Values wrap around [0, 1), so the small step is symmetric.
#include <array>
#include <cstdint>
#include <vector>

#include "renderer/sampling/sample_stream.h"

namespace pathfarm {

class PrimarySamples {
 public:
  enum Stream { kCamera = 0, kLight = 1, kConnection = 2 };
  static constexpr int kStreams = 3;
  // Deviation of one small step (pbrt-v3's default).
  static constexpr double kSmallStepSigma = 0.01;

  // The next state of a chain: a large or a small step from this one.
  PrimarySamples nextStep(bool large) const;

  // Coordinate `index` of `stream`, brought up to date with numbers from `random`.
  double get(int stream, size_t index, SampleStream& random);
  // Sets a coordinate outright, as a mutation of that coordinate alone does (the
  // temporal step moves the time coordinate only); it counts as up to date.
  void set(int stream, size_t index, double value, SampleStream& random);

 private:
  struct Coordinate {
    double value = 0;
    int64_t lastModified = -1;  // the step it was last brought up to date at
  };
  Coordinate& at(int stream, size_t index);

  std::array<std::vector<Coordinate>, kStreams> streams_;
  int64_t step_ = 0;            // accepted steps since the seed
  int64_t lastLargeStep_ = 0;   // the seed counts as a large step
};

}  // namespace pathfarm
