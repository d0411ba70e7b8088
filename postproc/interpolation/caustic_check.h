#pragma once
// Moving caustics are re-rendered, not reconstructed. Light that a moving mirror or glass
// focuses onto a diffuse surface (the renderer's `moving_caustic.Y`,
// renderer/decomposition/path_decomposer.h) moves with the object that focuses it, not with
// the surface it falls on: the surface's motion does not carry it between keyframes, optical
// flow on a keyframe's few noisy samples does not find it, and a quarter-sample keyframe
// filtered at half resolution spreads it out, so the bright spot under a glass ball fades.
// A pixel is flagged where, over the (2 radius + 1)^2 window around it,
//   sum of moving_caustic.Y > share * sum of the beauty's luminance + z * sqrt(sum of the
//   variance bound of the beauty's luminance, from `variance.R/G/B`; none without them),
// and at least `minPixels` pixels of the window saw some of it (one sample of a weak, wide
// caustic is a firefly, not a spot worth re-rendering); the flags then grow by `margin`
// pixels, since a render with few samples finds only part of a caustic's extent.
// The noise term is for light a moving mirror or glass spreads over a whole scene: a
// moving glass ball reflects a lamp onto every surface around it, a few per cent of their
// light. In a 4-spp render that glow arrives in rare, heavy samples, and without the term
// a window holding two or three of them passed the share (on the dolly at 640x360, 4 % of
// the picture in scattered blocks on the floor, flagged for this cause alone). It is for
// such renders: the farm's keyframe task, whose keyframe carries its caustic into every
// frame interpolated from it, checks without it (z = 0).
#include <cstdint>
#include <vector>

#include "image/frame_image.h"

namespace pathfarm {

struct CausticCheckSettings {
  int radius = 2;      // the window: (2 radius + 1)^2 pixels
  float share = 0.1f;  // of the beauty's luminance over the window
  int minPixels = 3;   // pixels of the window that saw some of the caustic
  float z = 2.0f;      // standard deviations of the window's light its caustic must exceed the share by
  int margin = 2;      // pixels the flags grow by
};

// How many rows (and columns) away a pixel's flag reads: a band of a frame's rows with this
// many rows around it has its rows' flags in the same bits as the whole frame.
inline int causticCheckReach(const CausticCheckSettings& settings) { return settings.radius + settings.margin; }

// One byte per pixel, 1 where a moving caustic should be re-rendered. A frame without
// `moving_caustic.Y` (rendered without a decomposition) has none. Throws
// std::invalid_argument when the beauty R, G, B is missing.
std::vector<uint8_t> movingCausticPixels(const FrameImage& frame, const CausticCheckSettings& settings = {});

}  // namespace pathfarm
