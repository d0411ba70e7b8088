#pragma once
// Fireflies taken out before NL-means and their light spread smoothly over their surface.
//
// A firefly is a pixel whose mean is carried by one rare, bright sample (a caustic path
// found by chance). NL-means cannot average it away: its variance is as large as its
// value, so its distance to every neighbour is small, and every pixel whose search window
// holds it takes it in. Its light ends up as a flat box with sharp edges, the size of the
// search window (11x11 with neighbour frames), and many of them make a blocky wall; a
// keyframe's box, upsampled and interpolated, sits in a dozen frames.
//
// splitFireflies finds them and takes their excess out of the color:
//   firefly      a valid pixel p with L(p) > factor * m(p), where L is the mean of the
//                color channels and m the mean of L over the valid pixels of the 5x5
//                window around p, p and the brightest of them left out (at least
//                minNeighbours of them): another firefly nearby does not lift m, but a
//                crowd of them (a caustic that few samples found) does, and keeps its
//                light where it was found; beyond the neighbours' noise, L(p) - m(p) >
//                outlierErrors * e(p) with e the median of their standard errors (sqrt
//                of the mean variance over the channels); and with a standard error of
//                its own of at least minRelativeError * L(p) (a bright detail that every
//                sample sees has a small one, and is kept);
//   clamped      its color scaled to luminance factor * m(p), its variance by the square
//                of that scale (the same relative error);
//   excess       the rest of its color, spread over the pixels within a radius on the
//                same surface (the same object id, normals within 25 degrees, when
//                given) with weights g(d) * l(q): g a Gaussian of sigma radius / 2, l(q)
//                the mean luminance of the valid pixels of q's 3x3 window on q's surface
//                that are no fireflies, so that a shadow beside the firefly takes little. The radius grows with
//                the excess, so that the spread's peak is about `glow` times m(p), up to
//                maxRadius: a firefly fifty times its wall becomes a glow 19 pixels in
//                radius, a tenth as bright as the wall, not a spot. The weights are
//                normalized over those pixels plus the invalid ones (pixels without a
//                sample, counted at l = m(p): their share is dropped, as their filter
//                decides their value). A firefly whose weights are all 0 is left as it is.
// The clamped color plus the excess holds the same light as the input wherever every
// pixel of the surface is valid; the excess is smooth, so the filter's output plus it
// shows no square.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "postproc/filters/nlmeans.h"

namespace pathfarm {

struct FireflySettings {
  float factor = 2.0f;            // a firefly exceeds this multiple of its neighbours' level
  float outlierErrors = 4.0f;     // and exceeds it by this many of their standard errors
  float minRelativeError = 0.3f;  // and its own standard error is at least this share of its value
  int minNeighbours = 3;          // valid pixels of the 5x5 window needed to judge
  float glow = 0.1f;              // the spread's peak, as a share of the neighbours' level
  int maxRadius = 32;             // of the spread
};

// What guides the spread; either may be null (then it does not restrict).
struct FireflySurface {
  const Planes* normal = nullptr;    // 3 channels
  const Planes* objectId = nullptr;  // 1 channel, exact match
};

struct FireflySplit {
  Planes excess;          // the fireflies' light, spread; same size and channels as color
  std::vector<size_t> fireflies;  // the pixels clamped, in row order
};

// How far the input reaches into a pixel's result: the color, clamped color and excess of
// a pixel depend only on the pixels (and their validity and surface) within this many
// pixels of it (a spread of maxRadius, whose weights depend on the 3x3 light of the
// pixels it covers, from fireflies judged on their 5x5 windows).
int fireflyReach(const FireflySettings& settings);

// Clamps the fireflies of `color` (and scales their `variance`) in place and returns their
// spread excess. `valid` (empty: every pixel) marks pixels that hold a sample; a pixel
// with a non-finite color or variance is invalid too. Throws std::invalid_argument for
// mismatched sizes or channel counts.
FireflySplit splitFireflies(Planes& color, Planes& variance, const std::vector<float>& valid,
                            const FireflySurface& surface, const FireflySettings& settings = {});

}  // namespace pathfarm
