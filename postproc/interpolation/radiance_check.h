#pragma once
// Checking an interpolated frame's light against the frame's own cheap render. Depth and
// presence (feature_check.h) say where surfaces are, not how they are lit: a pixel a
// keyframe could not see (disoccluded behind a moving object) takes the other keyframe's
// light, so a shadow or a reflection is put where it was at that keyframe — a ghost of
// the moving object. The few samples of the in-between frame are noisy pixel by pixel but
// not over a window: per component c and pixel p, over the (2 radius + 1)^2 window around p,
//   |sum interpolated <c>.color - sum features' <c>.color| > z * sqrt(sum of the features'
//   <c>.variance)  and  > relative * (sum of the features' beauty)
// (luminances; the variance of a luminance bounded above by (sum_k w_k sigma_k)^2) flags p:
// a difference the feature render's noise cannot explain, large enough to see.
// A real difference flags every window that holds it, a solid region; what the flags keep
// is the regions holding a solid square of side 2 solidRadius + 1 (solid_regions.h). The
// feature render's few samples underestimate their own variance where rare paths carry
// much of the light (a caustic's fireflies on a ceiling), and there the statistic grazes
// its threshold in scattered, thin specks that a re-render at full samples, denoised among
// themselves, would turn into blotches.
//
// A region grows from there into the connected pixels whose windows differ by the weaker
// `growZ` and `growRelative` (hysteresis, as an edge detector follows an edge). The light
// just outside a region flagged at a tenth is often still off by nearly a tenth: a moving
// soft shadow interpolated between keyframes that both saw it elsewhere. Re-rendered
// inside and interpolated outside, the outline showed as a step. Growth needs a strong
// region to start from, so noise alone still flags nothing, and it stops `growReach`
// pixels out: far enough to take in a soft shadow's edge, not so far that a light a few
// per cent off over a whole wall is all rendered again.
#include <cstdint>
#include <vector>

#include "image/frame_image.h"

namespace pathfarm {

struct RadianceCheckSettings {
  int radius = 3;
  float z = 4.0f;
  float relative = 0.1f;
  int solidRadius = 1;  // 0: keep every flag
  float growZ = 3.0f;          // a region grows through pixels passing these weaker bounds
  float growRelative = 0.04f;  // (growRelative >= relative: no growth),
  int growReach = 4;           // by at most this many pixels
};

// How many rows (and columns) away a pixel's flag reads: its window, the solid square
// around it and the growth. A band of rows with this many rows around it has its rows'
// flags in the same bits as the whole frame.
inline int radianceCheckReach(const RadianceCheckSettings& settings) {
  return settings.radius + 2 * settings.solidRadius + settings.growReach;
}

// One byte per pixel, 1 where any component's light disagrees. Throws
// std::invalid_argument for frames of different sizes or a missing channel (naming it).
std::vector<uint8_t> radianceMismatch(const FrameImage& interpolated, const FrameImage& features,
                                      const RadianceCheckSettings& settings = {});

}  // namespace pathfarm
