#pragma once
// Checks of what frame interpolation (frame_interpolation.h) and the motions it follows
// (component_motion.h) are given: keyframes of one layout, their channels and the motion
// fields. Each throws std::invalid_argument naming what is wrong and where.
#include <string>
#include <vector>

#include "image/frame_image.h"
#include "postproc/filters/warp.h"

namespace pathfarm {

// The channel `name` of `frame`, checked present and finite; `label` names the frame.
const std::vector<float>& finiteChannel(const FrameImage& frame, const std::string& name, const std::string& label);

// `field` is width x height, with finite motion wherever it is valid.
void checkField(const MotionField& field, int width, int height, const std::string& what);

// `a` and `b` have one size and one decomposition.
void checkSameLayout(const FrameImage& a, const FrameImage& b, const std::string& labelA, const std::string& labelB);

}  // namespace pathfarm
