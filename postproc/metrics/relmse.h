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

// A mean of many per-value terms, kept as sums so that estimates over several frames add
// up, with the standard error of the mean. Neighbouring terms are not independent (a
// filtered image errs alike over an area; a pixel's denominator is its neighbours'
// values), so the error is taken from the spread of the sums over 8x8-pixel blocks, which
// holds while blocks are independent of each other.
struct MeanEstimate {
  double sum = 0, count = 0;
  // Over blocks b with sum s_b of n_b terms: the sums of s_b^2, s_b n_b and n_b^2.
  double blockSquares = 0, blockCross = 0, blockCountSquares = 0;
  double blocks = 0;
  double mean() const { return count > 0 ? sum / count : 0; }
  double standardError() const;
  void addBlock(double blockSum, double blockCount);
  MeanEstimate& operator+=(const MeanEstimate& other);
};

// The relMSE `image` has against the truth, estimated without the truth, from an
// independent unbiased render that carries its variance: the mean of
// ((image - reference)^2 - variance) / (d^2 + 0.01), since an independent reference adds
// its variance to every squared error. d is the mean of the reference's 8 neighbours of
// the pixel (those inside the frame), not its own noisy value: a denominator sharing the
// numerator's noise would bias the estimate upward wherever the image is brighter than the
// truth and downward where darker. Near zero, or a little below it, when the image is
// within the reference's noise of the truth. Throws std::invalid_argument without the
// reference's variance channels or for frames of different sizes.
MeanEstimate relMseLessReferenceNoise(const FrameImage& image, const FrameImage& reference);
// The same render's own relMSE against the truth, from its variance, with the same
// denominators.
MeanEstimate ownRelMseFromVariance(const FrameImage& reference);

}  // namespace pathfarm
