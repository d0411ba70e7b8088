#pragma once
// Which pixel of the next frame a pixel's temporal offset goes through (Manzi et al.
// 2016, Section 4.2): the primary motion of what the pixel centre sees, checked forward
// and backward (the next frame's backward motion must lead back within 1 pixel), made
// one-to-one by letting the point nearest to the camera keep a contested target.
// Pixels without such a correspondence get no temporal constraint.
#include <cstdint>
#include <vector>

#include "renderer/accel/frame_geometry.h"
#include "renderer/scene/camera.h"

namespace pathfarm {

// Per pixel of `frame`, the index of its pixel in frame + 1, or -1. Without motion
// vectors every pixel keeps its own position.
std::vector<int32_t> temporalCorrespondence(const FrameGeometry& current, const FrameGeometry& next,
                                            const Camera& camera, int width, int height, bool followMotion);

}  // namespace pathfarm
