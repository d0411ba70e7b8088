#pragma once
// The error a frame has against the truth, estimated per value from an independent,
// unbiased reference that carries its variance (relmse.h, relMseLessReferenceNoise), and
// summed per block of pixels: the unit in which an error's uncertainty is resampled
// (error_interval.h). Neighbouring terms are not independent (a filtered image errs alike
// over an area; the denominators are neighbours' values), blocks far enough apart nearly
// are.
//
// A term is ((x - r)^2 - Var r) / (d^2 + 0.01): an independent reference adds its variance
// to every squared error, so subtracting it leaves the squared error against the truth in
// expectation; d is the mean of the reference's 8 neighbours of the pixel, not its own
// noisy value, which would share the numerator's noise.
#include <cstdint>
#include <vector>

#include "image/frame_image.h"

namespace pathfarm {

inline constexpr int kErrorBlock = 8;  // pixels along a block's edge

// Per-block sums of terms and their counts, blocks in a fixed order; a whole figure is
// sum / count over every block.
struct BlockedTerms {
  std::vector<double> sums, counts;
  double mean() const;
  void append(const BlockedTerms& other);
};

// The terms of independent measurements of the same blocks (several renders of one frame),
// averaged block by block: each block then holds the mean of its measurements, and its
// spread between blocks is what that mean's is. Throws std::invalid_argument for no
// measurement or for terms over different numbers of blocks.
BlockedTerms averageOf(const std::vector<BlockedTerms>& measurements);

// The beauty's terms of `image` against `reference`, over the pixels whose `kept` byte is
// non-zero (every pixel without `kept`), in blocks of `block` pixels; blocks with no pixel
// kept are left out, and so are values that are not finite (a damaged pixel is counted
// apart by the figures that report it, image_metrics.h). Without `image`, the terms are the reference's own expected error,
// Var r / (d^2 + 0.01). Throws std::invalid_argument without the reference's variance
// channels or for frames of different sizes.
BlockedTerms errorTerms(const FrameImage* image, const FrameImage& reference, const std::vector<uint8_t>* kept = nullptr,
                        int block = kErrorBlock);

// The terms of the change from `before` to `after` against the reference's change, in
// blocks of kErrorBlock: ((dx - dr)^2 - Var r_before - Var r_after) / (dd^2 + 0.01), dd the
// neighbours' mean of dr (the temporal error, image_metrics.h, against the truth).
BlockedTerms temporalTerms(const FrameImage& before, const FrameImage& after, const FrameImage& referenceBefore,
                           const FrameImage& referenceAfter);

// The terms of every 16x16 tile (aligned to the frame's origin, edge tiles partial) in
// blocks of 4x4 pixels, for the worst tile's figure (error_interval.h, maxOfMeansInterval).
// Tiles with fewer than kMinTileBlocks blocks of kept pixels are left out: a tile the
// stage flagged almost whole says little and would often be the noisiest.
inline constexpr size_t kMinTileBlocks = 8;
std::vector<BlockedTerms> tileTerms(const FrameImage& image, const FrameImage& reference,
                                    const std::vector<uint8_t>* kept = nullptr);

}  // namespace pathfarm
