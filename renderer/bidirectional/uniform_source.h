#pragma once
// Where bidirectional sampling takes its uniform numbers from. The frame renderer reads a
// pixel sample's SampleStream; primary-sample-space Metropolis (Kelemen et al. 2002)
// implements it over its mutable vector of primary samples, with one source each for the
// camera subpath, the light subpath and the connection.
#include "renderer/math/vecmath.h"
#include "renderer/sampling/sample_stream.h"

namespace pathfarm {

class UniformSource {
 public:
  virtual ~UniformSource() = default;
  // A number in [0, 1).
  virtual float next1D() = 0;
  Vec2f next2D() {
    const float a = next1D();
    return {a, next1D()};
  }
};

// A SampleStream as a UniformSource.
class StreamSource final : public UniformSource {
 public:
  explicit StreamSource(SampleStream& stream) : stream_(stream) {}
  float next1D() override { return stream_.next1D(); }

 private:
  SampleStream& stream_;
};

}  // namespace pathfarm
