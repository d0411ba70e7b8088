#pragma once
// Backward warping of a neighbour frame onto the current frame along the current frame's
// motion (Zimmer et al. 2015, Section 6): pixel p of the current frame looks its value up
// at p + motion(p) in the neighbour, so the warped planes line up with the current frame
// pixel for pixel. For the previous frame the motion is the current frame's
// `motion_back`, for the next frame its `motion` (docs/decomposition.md).
//
// Coordinates are pixel indices (pixel (i, j)'s centre is (i, j)); the renderer's motions
// are differences of continuous film positions, so they apply unchanged.
#include <string>
#include <utility>
#include <vector>

#include "image/frame_image.h"
#include "postproc/filters/nlmeans.h"

namespace pathfarm {

enum class NeighbourFrame { Previous, Next };

enum class WarpLookup {
  Bilinear,  // colors, variances, continuous features
  Nearest,   // ids: never blended
};

// Where each pixel of the current frame comes from in a neighbour frame.
struct MotionField {
  int width = 0, height = 0;
  std::vector<float> x, y;   // pixel p maps to p + (x[p], y[p]) in the neighbour
  std::vector<float> valid;  // 1 where the motion holds (empty: everywhere)
  // A window of rows: the field is rows [top, top + height) of a frame frameHeight rows
  // tall (0: the field is the frame), and its pixels map by their rows in that frame.
  int top = 0, frameHeight = 0;

  int rowsOfFrame() const { return frameHeight > 0 ? frameHeight : height; }
};

// The current frame's motion towards `neighbour`: `<prefix>motion_back.X/Y` for the previous
// frame, `<prefix>motion.X/Y` for the next, with `<prefix>motion_valid.Y` when the frame has
// it. `prefix` is "" for the frame-wide (primary) motion or "<component>." for a
// component's. Throws std::invalid_argument naming a missing channel after `label`.
MotionField motionTowards(const FrameImage& current, NeighbourFrame neighbour, const std::string& prefix,
                          const std::string& label);

// 1 where the pixel's source lies inside the neighbour image (inside the pixel footprints:
// [-0.5, width - 0.5) x [-0.5, rowsOfFrame() - 0.5)) and its motion is valid and finite, else 0.
std::vector<float> warpValidity(const MotionField& motion);

// The rows [first, end) of the neighbour frame that warpPlanes reads for the valid pixels
// (warpValidity) of `motion`; {0, 0} when none is valid.
std::pair<int, int> warpSourceRows(const MotionField& motion);

// Each plane of `neighbour` looked up at p + motion(p): bilinear between the four nearest
// pixel centres, or the nearest pixel. `neighbour` is the motion field's width and holds
// rows [neighbourTop, neighbourTop + its height) of the frame (the field's rows, or those
// warpSourceRows names, or more). Lookups are clamped to the frame and to those rows, so
// where warpValidity is 0 the value is an edge's (or, for a non-finite motion, the pixel at
// p itself): plausible, but not to be used. An integer motion copies pixels exactly. The
// warped value of a valid pixel is the same bits whatever rows the field and `neighbour`
// hold. Throws std::invalid_argument for mismatched sizes.
Planes warpPlanes(const Planes& neighbour, const MotionField& motion, WarpLookup lookup = WarpLookup::Bilinear,
                  int neighbourTop = 0);

}  // namespace pathfarm
