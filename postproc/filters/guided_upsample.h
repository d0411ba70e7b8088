#pragma once
// Guided-filter joint upsampling (He, Sun and Tang 2013) as Zimmer et al. 2015 (Section
// 5.2) use it: a low-resolution image is upsampled by an integer factor, guided by
// full-resolution features (a multi-channel guide with the epsilon-regularized covariance
// solve). Pixels whose result comes out negative are reported for re-rendering.
//
// How it is computed (the full-resolution guided filter, not the "fast" one):
//  * the input p is the low-resolution image box-upsampled to full resolution (every
//    full-resolution pixel takes the value of the low-resolution pixel covering it);
//  * every full-resolution pixel k has a window w_k of radius R = radius * factor
//    full-resolution pixels ((2R+1)^2 pixels, clipped at the image border and normalized
//    by the clipped count), so `radius` is in low-resolution pixels;
//  * per window, the linear model p ~ a_k^T I + b_k with
//      a_k = (Sigma_k + epsilon U)^-1 cov_k(I, p),  b_k = mean_k(p) - a_k^T mean_k(I),
//    Sigma_k the guide's channel covariance in w_k (solved by Cholesky per pixel, in
//    double), one a_k column per input channel;
//  * q_i = mean_{k: i in w_k}(a_k)^T I_i + mean_{k: i in w_k}(b_k).
// Where p is an affine function of the guide within every window (a piecewise-constant
// image whose edges the guide shares, aligned with the low-resolution pixels), the result
// reproduces it to O(epsilon / local guide variance).
//
// Box filters are O(1) per pixel: running sums in double, vertical then horizontal. The
// image is cut into strips of fixed height, each computed on its own (with the rows of
// its windows around it), so the result does not depend on the number of threads.
//
// A band of rows of a taller frame (a filter task's window of rows) can be upsampled alone:
// given the rows guidedUpsampleReads names, its rows are the same bits as the whole
// frame's, since the strips are placed by frame rows and none reads past the rows given.
#include <cstddef>
#include <vector>

#include "postproc/filters/nlmeans.h"

namespace pathfarm {

struct GuidedUpsampleSettings {
  int factor = 2;        // integer upsampling factor (>= 1)
  int radius = 2;        // window radius, in low-resolution pixels (>= 0)
  float epsilon = 1e-3f; // regularization of the guide's covariance (> 0), in guide units^2
  int threads = 0;       // worker threads; 0: the hardware's. Results do not depend on it.
  // For a band of a taller frame: the frame row of the planes' first row (a multiple of
  // factor), and the frame rows [onlyFirst, onlyEnd) to compute (all when equal; the
  // result's other rows are 0, not rerendered).
  int firstRow = 0;
  int onlyFirst = 0, onlyEnd = 0;
};

// Frame rows first .. end - 1.
struct FrameRows {
  int first = 0, end = 0;
};

// The full-resolution rows of a frame `height` rows tall that guidedUpsample reads to
// compute rows `wanted` (the low-resolution input's are these divided by the factor): the
// strips holding them and every row their windows reach, widened to multiples of the factor.
FrameRows guidedUpsampleReads(const FrameRows& wanted, int height, const GuidedUpsampleSettings& settings);

struct GuidedUpsampleResult {
  Planes image;                 // full resolution, the channels of `low`
  std::vector<float> rerender;  // per pixel, 1 where a channel came out negative or NaN
                                // (those channels are then set to 0; the others are kept)
  std::vector<float> deficit;   // per pixel, the largest amount clamped away (+inf for NaN)
  size_t negativePixels = 0;    // the number of pixels with rerender == 1
};

// `low` is width/factor x height/factor; `guide` is full resolution (any channel count).
// Throws std::invalid_argument when the sizes do not fit the factor, a plane has the
// wrong size, either image has no channel, or a setting is out of range (a band's rows
// outside the planes, or a first row that is not a multiple of the factor).
GuidedUpsampleResult guidedUpsample(const Planes& low, const Planes& guide, const GuidedUpsampleSettings& settings);

}  // namespace pathfarm
