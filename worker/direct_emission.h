#pragma once
// Light seen directly from the camera is kept out of the keyframe filters. It carries no
// Monte Carlo noise beyond the pixel's coverage, and its edges are the sharpest in the
// frame: denoising blurs them, and after 2x2 downsampling no guide feature restores them
// (an emitter a few pixels wide spills over its neighbours). So it is taken out of the
// component the decomposition gives zero-bounce emission to (normally the residual),
// the rest is filtered, and the full-resolution emission is added back.
//
// Per pixel the directly seen emission is min(color, emission feature) of that component,
// channel by channel: the emission feature is the first non-specular vertex's emission
// averaged over the pixel's samples, which is the component's zero-bounce color.
#include <string>

#include "image/frame_image.h"

namespace pathfarm::farm {

// Removes the directly seen emission from the frame's beauty and the receiving component's
// color (and irradiance) and returns it as `direct_emission.R/G/B`.
FrameImage takeDirectEmission(FrameImage& frame);
// Adds it back to the beauty and the component's color (and irradiance, recomputed).
void addDirectEmission(FrameImage& frame, const FrameImage& emission);

}  // namespace pathfarm::farm
