#pragma once
// One stream of a PSSMLT state read as the uniform numbers of a path sampler: the
// sampler's i-th number is coordinate start + i of the stream, brought up to date lazily.
#include "renderer/bidirectional/uniform_source.h"
#include "renderer/metropolis/pssmlt/primary_samples.h"

namespace pathfarm {

class PrimarySource final : public UniformSource {
 public:
  PrimarySource(PrimarySamples& samples, int stream, size_t start, SampleStream& random)
      : samples_(samples), stream_(stream), next_(start), random_(random) {}

  float next1D() override {
    // A double just below 1 would round to 1.0f: keep the float below 1 as promised.
    return std::min(static_cast<float>(samples_.get(stream_, next_++, random_)), 0x1.fffffep-1f);
  }

 private:
  PrimarySamples& samples_;
  int stream_;
  size_t next_;
  SampleStream& random_;
};

}  // namespace pathfarm
