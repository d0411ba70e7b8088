#pragma once
// The buffers a gradient-domain render writes for one frame (docs/gradient-domain.md),
// as the screened Poisson reconstruction reads them. Per color channel c in R, G, B:
//   primal.c       the primal image without emitters seen directly from the camera
//   gradient_x.c   I(x+1, y) - I(x, y), stored at (x, y); the last column is unused
//   gradient_y.c   I(x, y+1) - I(x, y), stored at (x, y); the last row is unused
//   direct_emission.c  emitters seen directly, added back after reconstruction
// and optionally the temporal difference towards the next frame (Manzi et al. 2016):
//   temporal.c     I_next(target(p)) - I(p), stored at p of this frame
//   temporal.target.X/Y  the integer pixel target(p) of the next frame
//   temporal.valid.Y     1 where p has a one-to-one correspondence, else 0
//   mixed_x.c      the next frame's difference minus this frame's, from the temporal
//                  offset frame's own spatial differences:
//                  (I_next(target(p) + x) - I_next(target(p))) - (I(p + x) - I(p)),
//                  meaningful where target(p + x) = target(p) + x; mixed_y.c likewise
// Each of these six value layers may come with "<layer>.variance.c", the variance of its
// per-pixel mean; the reconstruction trusts a row less the larger it is (poisson_system.h).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "image/frame_image.h"

namespace pathfarm {

inline constexpr std::array<const char*, 3> kColorChannels{"R", "G", "B"};

struct GradientFrame {
  using Color = std::array<std::vector<float>, 3>;

  int width = 0, height = 0;
  Color primal, gradientX, gradientY, directEmission;
  Color temporal, mixedX, mixedY;       // empty without a temporal layer
  std::vector<int32_t> temporalTarget;  // pixel index in the next frame, -1 for none
  // Per layer, in the order primal, gradient_x, gradient_y, temporal, mixed_x, mixed_y:
  // the variance of each pixel's mean summed over the three channels; empty where the
  // image has no variance for the layer.
  static constexpr size_t kLayers = 6;
  static constexpr std::array<const char*, kLayers> kLayerNames{"primal",   "gradient_x", "gradient_y",
                                                                "temporal", "mixed_x",    "mixed_y"};
  std::array<std::vector<float>, kLayers> variance;

  size_t pixelCount() const { return static_cast<size_t>(width) * static_cast<size_t>(height); }
  bool hasTemporal() const { return !temporalTarget.empty(); }

  // Reads the layers above (a temporal layer needs its mixed layers); throws
  // std::invalid_argument naming `label` and the first missing channel. Targets outside
  // the image, non-finite temporal values and targets claimed by more than one pixel (all
  // but the first in scanline order) are invalid. A layer's variance is read when all
  // three of its channels are there.
  static GradientFrame fromImage(const FrameImage& image, const std::string& label);
};

}  // namespace pathfarm
