#pragma once
// Error metrics against a reference (DESIGN.md's data contract).
#include <string>
#include <vector>

#include "image/frame_image.h"

namespace pathfarm {

// One value's term of relMSE: (x - ref)^2 / (ref^2 + 0.01).
inline double relativeSquaredError(double x, double ref) { return (x - ref) * (x - ref) / (ref * ref + 0.01); }

// Relative MSE: the mean over pixels and channels of (x - ref)^2 / (ref^2 + 0.01).
double relMse(const std::vector<float>& image, const std::vector<float>& reference);
// relMSE over the named channels of two frames of equal size (default: the beauty).
double relMse(const FrameImage& image, const FrameImage& reference,
              const std::vector<std::string>& channels = {"R", "G", "B"});

// The relMSE an unbiased render is expected to have against the truth, from the variance
// of its per-pixel means ("variance.R/G/B", as pt writes them): the mean over pixels and
// channels of variance / (value^2 + 0.01). For a reference, it is the floor under which
// the errors measured against it say nothing. Throws std::invalid_argument without the
// variance channels.
double expectedRelMse(const FrameImage& image);

}  // namespace pathfarm
