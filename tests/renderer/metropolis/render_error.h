#pragma once
// Errors of rendered frames against a path-traced reference (DESIGN.md's relMSE), and the
// error path tracing itself is expected to have at a given sample count.
#include <string>

#include "image/frame_image.h"

namespace pathfarm::test_support {

// relMSE of `image` against `reference` over R, G, B.
inline double relMse(const FrameImage& image, const FrameImage& reference) {
  double sum = 0;
  size_t n = 0;
  for (const char* c : {"R", "G", "B"}) {
    const auto& x = image.channel(c);
    const auto& r = reference.channel(c);
    for (size_t i = 0; i < x.size(); ++i, ++n) sum += (x[i] - r[i]) * (x[i] - r[i]) / (r[i] * r[i] + 0.01);
  }
  return sum / static_cast<double>(n);
}

// The relMSE a path-traced image with `spp` samples is expected to have, from the
// reference's variance of the pixel mean at its own sample count.
inline double pathTracedRelMse(const FrameImage& reference, int referenceSpp, double spp) {
  double sum = 0;
  size_t n = 0;
  for (const char* c : {"R", "G", "B"}) {
    const auto& r = reference.channel(c);
    const auto& v = reference.channel(std::string("variance.") + c);
    for (size_t i = 0; i < r.size(); ++i, ++n) sum += v[i] * referenceSpp / spp / (r[i] * r[i] + 0.01);
  }
  return sum / static_cast<double>(n);
}

}  // namespace pathfarm::test_support
