#pragma once
// The motions frame interpolation (frame_interpolation.h) moves each layer along between
// two keyframes: the primary motion chained over the rendered frames between them, and a
// component's irradiance motion, the optical flow of its irradiance.
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "image/frame_image.h"
#include "postproc/filters/warp.h"

namespace pathfarm {

// One layer's motion between the keyframes. forward: pixel p of K0 is at p + forward(p) in
// K1; backward: pixel p of K1 is at p + backward(p) in K0. `valid` (empty: everywhere)
// marks where the motion holds.
// irradianceForward/irradianceBackward: the same for the component's irradiance (its optical
// flow between the keyframes, irradiance_flow.h), used when hasIrradianceMotion; their
// `valid` (empty: everywhere) marks where the flow holds, elsewhere the primary motion is used.
struct ComponentMotion {
  ComponentMotion() = default;
  ComponentMotion(MotionField primaryForward, MotionField primaryBackward)
      : forward(std::move(primaryForward)), backward(std::move(primaryBackward)) {}

  MotionField forward;
  MotionField backward;
  MotionField irradianceForward;
  MotionField irradianceBackward;
  bool hasIrradianceMotion = false;
};

// Per component name; "" is the frame-wide primary motion (the color-only baseline).
struct ComponentMotions {
  std::map<std::string, ComponentMotion> components;
};

// Chains the per-frame motions of consecutive rendered frames K0 = frames.front() ..
// K1 = frames.back(): forward p -> p + m_0(p) -> q + m_1(q) -> ... along `<c>.motion`,
// backward along `<c>.motion_back` from K1, with bilinear lookups of the motion (nearest for
// `<c>.motion_valid.Y`). Valid where every link is valid and every position is inside the
// image. Produces every component of the frames' decomposition and "" from the frame-wide
// `motion`/`motion_back`. Throws std::invalid_argument for fewer than two frames,
// mismatched sizes or decompositions, missing motion channels or non-finite motion.
ComponentMotions concatenatePrimaryMotion(const std::vector<FrameImage>& frames);

}  // namespace pathfarm
