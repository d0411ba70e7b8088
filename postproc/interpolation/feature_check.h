#pragma once
// Checking an interpolated frame against the frame's own cheap render of its features.
// Interpolation moves the keyframes' content along the motion between them, which is the
// motion of the keyframes' instants: an object that turns back between two keyframes (a
// ball at the top of its bounce) is put where the keyframes agree it is, not where it is.
// A few samples of the in-between frame itself tell where every component's surface
// really is, and the pixels where the interpolation disagrees are re-rendered.
//
// Per component c of the interpolated frame's decomposition and pixel p, a mismatch is
//   depth      both have c at p (interpolated `<c>.depth.Z` > 0, features' `<c>.normal`
//              not (0, 0, 0)) and the depths differ by more than depthTolerance relative;
//   presence   only one of them has c at p, and there c is significant: its luminance
//              exceeds `significance` times the beauty's (features' `<c>.color` against
//              their R, G, B; interpolated `<c>.color` against its R, G, B).
#include <cstdint>
#include <vector>

#include "image/frame_image.h"

namespace pathfarm {

struct FeatureCheckSettings {
  float depthTolerance = 0.05f;
  float significance = 0.02f;
};

// One byte per pixel, 1 where any component mismatches. Throws std::invalid_argument for
// frames of different sizes or a missing channel (naming it).
std::vector<uint8_t> featureMismatch(const FrameImage& interpolated, const FrameImage& features,
                                     const FeatureCheckSettings& settings = {});

}  // namespace pathfarm
