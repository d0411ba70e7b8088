#pragma once
// What a gradient-domain render keeps of each pixel between sampling it and making the
// frame's layers (gradient_frame_renderer.h). A pixel's samples are summed, then reduced
// to means and variances of the mean, as floats, in an "estimates" image; neighbours meet
// only when the layers are made from estimates. So a frame can be sampled in windows,
// on several workers, and joined: the layers of joined windows are, bit for bit, those of
// the frame sampled whole, which goes through the same two steps.
//
// The estimates' channels, per pixel:
//   `drawn.Y`                       sample indices used;
//   `mixed_samples.Y`               with temporal offsets, the finite samples that traced the
//                                   temporal offset's spatial offsets;
//   `<m>.R/G/B`, `<m>.variance.R/G/B` the mean and its variance of each moment m over the
//                                   finite samples: `own`, `direct`, `offset<k>`,
//                                   `difference<k>` (k = 0..3, the shift directions) and, with
//                                   temporal offsets, `temporal` and `mixed<k>` (over the
//                                   mixed samples);
//   `temporal.target.X/Y`           with temporal offsets, the pixel its offset goes
//                                   through in the next frame (-1: none).
#include <array>
#include <cstdint>
#include <vector>

#include "image/frame_image.h"
#include "renderer/integrators/sample_moments.h"

namespace pathfarm {

// One pixel's samples: what its base paths and their offsets added up to.
struct GradientPixelSums {
  uint32_t drawn = 0;         // sample indices used so far
  uint32_t samples = 0;       // finite samples accumulated
  uint32_t mixedSamples = 0;  // of which with the temporal offset's spatial offsets
  SampleMoments direct, own, temporal;  // own: the base's parts of its pixel, averaged over the 4 pairs
  std::array<SampleMoments, 4> offset, difference;
  std::array<SampleMoments, 4> mixed;  // the temporal offset's difference minus the base's, per direction
};

// The estimates of a width x height window from its pixels' sums (row by row). `targets`:
// per pixel, the index in the frame (`frameWidth` wide) of the pixel its temporal offset
// goes through, -1 for none; empty without temporal offsets.
FrameImage gradientEstimates(const std::vector<GradientPixelSums>& sums, int width, int height,
                             const std::vector<int32_t>& targets, int frameWidth);

// Estimates of a window with its corner at (x0, y0) of the frame.
struct PlacedEstimates {
  const FrameImage* estimates;
  int x0 = 0, y0 = 0;
};

// The gradient frame's layers from windows that cover the width x height frame once each,
// with the first window's attributes (`pathfarm.nonfinite_samples` summed over them).
// Throws std::invalid_argument for a window that leaves the frame, overlaps another or
// lacks a channel, and for a pixel no window covers.
FrameImage gradientFrameFromEstimates(const std::vector<PlacedEstimates>& windows, int width, int height);

// The per-pixel relative variance of the spatial differences (adaptive_sampling.h) of
// estimates of the whole frame.
std::vector<float> gradientRelativeVariance(const FrameImage& estimates);

}  // namespace pathfarm
