#pragma once
// Error metrics of an image against a reference, over chosen channels and an optional
// crop: relMSE (DESIGN.md's definition), MSE, PSNR and SMAPE. Reference pixels that are
// not finite are skipped and counted; a non-finite value in the image counts as an error
// of its own (it is kept out of the means and counted in `nonFinite`).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "image/frame_image.h"

namespace pathfarm {

struct Crop {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // [x0, x1) x [y0, y1)
};

struct ImageMetrics {
  double relMse = 0;
  double mse = 0;
  double psnr = 0;   // 10 log10(1 / MSE): a peak of 1, as for display-referred values
  double smape = 0;  // mean of 2|x - r| / (|x| + |r| + 0.01)
  // The image's values summed over the reference's (1: as bright overall). An offset of
  // the whole frame, which relMSE mixes with the noise, shows here alone.
  double brightness = 1;
  // Artifacts (DESIGN.md): the worst 16x16 tile's relMSE (tiles aligned to the frame's
  // origin, partial tiles included) and the share of the squared relative error that lies
  // in the worst 1 % of pixels (at least one pixel). A few wrong pixels show here even
  // when the mean is low.
  double worstTileRelMse = 0;
  double worstPercentShare = 0;
  size_t compared = 0;       // values that entered the means
  size_t skippedReference = 0;  // reference values that were not finite
  size_t nonFinite = 0;      // image values that were not finite
};

// The channels of a layer: "" for the beauty R, G, B; "diffuse_direct.color" for
// diffuse_direct.color.R/G/B; any other prefix takes every channel that starts with it.
// Throws std::invalid_argument naming the layer when the frame has none.
std::vector<std::string> layerChannels(const FrameImage& frame, const std::string& layer);

// Throws std::invalid_argument for different sizes, a missing channel or a crop outside.
// With `only`, just the pixels it sets are compared.
ImageMetrics compareImages(const FrameImage& image, const FrameImage& reference,
                           const std::vector<std::string>& channels, const std::optional<Crop>& crop = {},
                           const std::vector<uint8_t>* only = nullptr);

struct SequenceMetrics {
  std::vector<ImageMetrics> frames;
  double meanRelMse = 0;
  // Flicker: relMSE of the image's frame-to-frame differences against the reference's.
  double temporalRelMse = 0;
};

SequenceMetrics compareSequences(const std::vector<FrameImage>& images, const std::vector<FrameImage>& references,
                                 const std::vector<std::string>& channels, const std::optional<Crop>& crop = {});

}  // namespace pathfarm
