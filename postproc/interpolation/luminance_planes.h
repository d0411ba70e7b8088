#pragma once
// A frame's channels read as one luminance per pixel, for the checks that compare light
// over windows (radiance_check.h, caustic_check.h).
#include <string>
#include <vector>

#include "image/frame_image.h"

namespace pathfarm {

// The luminance of `<prefix>R/G/B` at every pixel; `whose` names the frame in the message
// of a missing channel (channelOf).
std::vector<double> luminancePlane(const FrameImage& frame, const std::string& prefix, const std::string& whose);

// From the variances `<prefix>R/G/B` of a pixel's mean, a bound on its luminance's:
// (sum_k w_k sigma_k)^2, which holds however the channels' noise is correlated.
std::vector<double> luminanceVarianceBound(const FrameImage& frame, const std::string& prefix,
                                           const std::string& whose);

}  // namespace pathfarm
