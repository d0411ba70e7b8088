#pragma once
// Post-process motion blur of a decomposed frame: every path-space component is integrated
// along its own motion over the exposure, and the blurred components are summed into the
// beauty R, G, B.
//
// The shutter: `exposure` is a fraction of the frame interval (1 = the full interval to the
// neighbours). Centered (the default) spans [-exposure/2, +exposure/2] around the frame:
// times before it move along `<c>.motion_back` scaled by |tau|, times after along
// `<c>.motion` scaled by tau; Opening spans [0, exposure] along `<c>.motion` only. The
// exposure is sampled at `steps` evenly spaced times (midpoints of equal sub-intervals).
// At each time the component is forward-splatted (forward_splat.h: bilinear footprints,
// the nearest `<c>.depth.Z` of any contribution, however weak, sets the reference and
// contributions within the depth tolerance are kept). Per pixel, with kept weight w: w >= 1
// takes the normalized splat; w < 1 takes the kept weighted sum plus (1 - w) * background,
// so the splat is energy-conserving (a zero-motion frame is returned exactly). The
// background is the pixel's own unmoved value where that surface stays in place and was
// hidden by the depth test, else the value of fully covered pixels, the rest filled from
// them deepest surface first (what a moving surface uncovers). The results of all times
// are averaged.
//
// Where a component's motion is undefined (`<c>.motion_valid.Y` < 0.5: specular paths the
// renderer does not track yet) it is inpainted: each such pixel takes the motion of the
// component's nearest pixel with valid motion, or, where the component has none at all,
// the frame-wide primary motion (the motion of the mirror or glass surface itself).
// A frame without a decomposition is blurred as one layer: the beauty along the frame-wide
// `motion`/`motion_back`, with `depth.Z`.
//
// Output: a copy of the frame with R, G, B and every `<c>.color.R/G/B` replaced by the
// blurred values, and attribute `pathfarm.motion_blur` = the exposure. Throws
// std::invalid_argument for a negative or non-finite exposure, steps < 1, a missing
// color/depth/motion channel (named) or a non-finite value in one.
#include "image/frame_image.h"

namespace pathfarm {

enum class Shutter { Centered, Opening };

struct MotionBlurSettings {
  int steps = 16;
  Shutter shutter = Shutter::Centered;
  float depthTolerance = 0.05f;
};

FrameImage motionBlur(const FrameImage& frame, float exposure, const MotionBlurSettings& settings = {});

}  // namespace pathfarm
