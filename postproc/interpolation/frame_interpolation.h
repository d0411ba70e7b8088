#pragma once
// Per-component frame interpolation with re-render masks (Zimmer et al. 2015, Section
// 5.3). Between two rendered keyframes K0 and K1 the frame at fraction s in (0, 1) is
// built per path-space component (docs/decomposition.md): K0's component is forward-splatted
// along s * motion(K0->K1) and K1's along (1 - s) * motion(K1->K0) (forward_splat.h:
// bilinear footprints, nearest surface by `<c>.depth.Z` wins within a relative tolerance),
// the two are blended with weights (1 - s) and s, and the components are summed into the
// beauty R, G, B.
//
// With the in-between frame's own features (LayeredKeyframes::inBetween), a component's
// color within a pixel of a texture edge (settings.textureEdge) is its interpolated
// irradiance times the frame's own reflectance: the edge is then where the frame has it, not
// where the motion moves the keyframes' to, blurred by the splat. Elsewhere the keyframes'
// reflectance is kept: it is as right there and far less noisy than the features' few samples.
//
// What is splatted: without an irradiance motion (ComponentMotion::hasIrradianceMotion
// false) the component's color `<c>.color.R/G/B` (its irradiance `<c>.irradiance.R/G/B`, or
// the color where a frame has none, is splatted alongside for the illumination test below).
// With one (addIrradianceFlow), as in the paper: the reflectance `<c>.reflectance.R/G/B` is
// splatted along the primary motion (forward/backward), the irradiance `<c>.irradiance.R/G/B`
// along the irradiance motion (s * irradianceForward from K0, (1 - s) * irradianceBackward
// from K1; where that motion is invalid, along the primary motion), each is combined as
// below, and the component's color is modulateIrradiance(irradiance, reflectance)
// (renderer/decomposition/effective_irradiance.h). A moving shadow on a static surface then
// moves with the shadow instead of cross-fading. This does not keep the components' sum
// exactly (the product of two blends is not the blend of the products, and where a
// keyframe's reflectance is below the guard its "irradiance" is the color). A pixel is a
// hole when either splat leaves it uncovered, one-sided when either is one-sided, and the
// illumination test uses the change of the irradiance splatted along the irradiance motion.
// The depth of both splats is the component's (below).
//
// Depth of the splat's depth test: `<c>.depth.Z`, except for a component the keyframe does
// not list as specular (`pathfarm.specular_components`) where `<c>.motion_valid.Y` is 1 and
// the frame has `depth.Z`: there the component's motion is the primary motion (its first
// non-specular vertex is the primary hit) and the frame-wide, less noisy `depth.Z` is used.
// The interpolated frame carries the same depth, which the feature check compares with
// the in-between frame's own `<c>.depth.Z`.
// Both the splat's and the combination's tests take it at the in-between instant: a pixel
// p whose motion leads to q in the other keyframe, whose motion (the same layer's) leads
// back within a pixel of p, has its depth blended with the other keyframe's at q by the
// fraction; elsewhere it keeps its own. Under a moving camera a near surface's depth
// changes between the keyframes by more than the tolerance, and as each keyframe saw it
// the nearer keyframe would win it alone.
//
// Combining the keyframes at a pixel: both splats cover it -> if one's depth is nearer than
// the other's by more than twice the depth tolerance it alone is kept, else the blend; one
// covers it -> that one ("seen in one keyframe only"); none covers it -> a hole: the
// best-effort value is the static blend (1 - s) K0(p) + s K1(p) of the component at the
// same pixel, and the pixel is masked if that value is significant.
//
// The re-render mask (channel `rerender.Y`, 1 = render this pixel) is the union of
//   holes         a component with no splat from either keyframe whose best-effort value is
//                 significant there;
//   silhouettes   the splat targets (nearest pixel) of K0/K1 pixels with `silhouette.Y` > 0.5
//                 (motion is unreliable there). A missing `silhouette.Y` means none;
//   untracked     pixels where a component is significant in K0 or K1 but its motion is
//                 invalid (specular paths the caller could not track, or a chain leaving the
//                 image); their targets are unknown, so the source pixel itself is marked. Their
//                 best-effort value: splatted along the frame-wide motion (key "") when
//                 untrackedFollowPrimary and it is given, else left to the hole rule;
//   illumination  a significant component seen in one keyframe only, where the component's
//                 irradiance changed between the keyframes nearby: the largest relative change
//                 |L(E0) - L(E1)| / max((L(E0) + L(E1)) / 2, irradianceFloor) (L: luminance of
//                 the splatted irradiances) over the pixels within illuminationRadius that both
//                 keyframes cover exceeds illuminationChange; with no such pixel nearby the
//                 change is unknown, and the pixel is marked when unknownChangeMasks.
// "Significant": the component's luminance there exceeds `significance` times the
// pixel's beauty luminance (and 1e-6). Masked pixels keep their best-effort value.
// The re-render rate (masked fraction) is in attribute `pathfarm.rerender_rate`.
//
// Color-only baseline (settings.colorOnly): the same code with one layer, the beauty
// R, G, B, frame-wide `depth.Z` and the frame-wide motion (ComponentMotions key ""); its
// output has no component channels and no `pathfarm.decomposition` attribute.
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "image/frame_image.h"
#include "postproc/interpolation/component_motion.h"

namespace pathfarm {

struct InterpolationSettings {
  bool colorOnly = false;         // the baseline: beauty along the frame-wide motion
  float depthTolerance = 0.05f;   // relative depth difference still read as one surface
  float minCoverage = 0.1f;       // splat weight below this is a hole
  float significance = 0.02f;     // of the pixel's beauty luminance
  float illuminationChange = 0.25f;  // relative irradiance change that masks one-sided pixels
  float irradianceFloor = 1e-3f;  // denominator floor of that relative change
  int illuminationRadius = 2;     // window of the change estimate
  // Whether a one-sided pixel with no two-sided pixel nearby (content entering the view,
  // a wide disocclusion) is masked. The farm's interpolate task checks every pixel's light
  // against the frame's own render instead (radiance_check.h), so it passes false.
  bool unknownChangeMasks = true;
  // Best effort for untracked pixels (still masked): splat them along the frame-wide motion
  // (ComponentMotions key "", when given) instead of leaving them to the static hole blend.
  bool untrackedFollowPrimary = true;
  // With the in-between frame's own features: a pixel is at a texture edge, and takes the
  // frame's own reflectance, where the splatted reflectance's luminance spans more than this
  // (relative) over its 3x3 neighbourhood.
  float textureEdge = 0.5f;
};

struct InterpolationResult {
  FrameImage frame;              // R, G, B, `<c>.color.R/G/B`, `<c>.depth.Z`, `rerender.Y`
  double rerenderRate = 0;       // fraction of pixels in the mask
  std::vector<uint8_t> mask;     // per pixel, 1 = re-render
  // Per pixel, 1 where that cause flags it (each always in the mask), and their counts.
  std::vector<uint8_t> holes, silhouettes, untracked, illumination;
  size_t holePixels = 0, silhouettePixels = 0, untrackedPixels = 0, illuminationPixels = 0;
};

// Throws std::invalid_argument for s outside (0, 1), mismatched sizes or decompositions,
// missing channels or motions (naming the frame and the layer) and non-finite values.
InterpolationResult interpolateFrameDetailed(const FrameImage& k0, const FrameImage& k1,
                                             const ComponentMotions& motions, float s,
                                             const InterpolationSettings& settings = {});

// One component of both keyframes, as LayeredKeyframes gives it.
struct KeyframeComponent {
  // Each keyframe's channels of the component (`<c>.*`) and depth.Z; of "" in the
  // color-only mode, the beauty and depth.Z.
  std::array<std::shared_ptr<const FrameImage>, 2> frames;
  std::shared_ptr<const ComponentMotion> motion;  // its motions between the keyframes
};

// The keyframes given a component at a time, so that an interpolation holds the components
// it is working on and not both keyframes whole (a 1080p pair of filtered keyframes is
// gigabytes). The same result, bit for bit, as interpolating the whole frames they are
// parts of.
struct LayeredKeyframes {
  // Each keyframe's frame-wide channels (`R`, `G`, `B`, `<buffer>.<channel>`: depth.Z,
  // silhouette.Y, motion) and attributes.
  std::array<const FrameImage*, 2> frameWide{};
  // A component ("" in the color-only mode); throws std::invalid_argument when it has no
  // motion. Called from several threads at once; what it returns is let go once the
  // component is read.
  std::function<KeyframeComponent(const std::string& component)> component;
  // The frame-wide motion, which untracked components follow (untrackedFollowPrimary), or null.
  const ComponentMotion* frameWideMotion = nullptr;
  // The in-between frame's own render of its features (feature_check.h), of the keyframes'
  // size, or null. Where it has a component's `<c>.reflectance`, the component's
  // interpolated irradiance at texture edges is modulated by it rather than by the
  // reflectance splatted from the keyframes (where both are above the guard).
  const FrameImage* inBetween = nullptr;
};
// Whole keyframes as LayeredKeyframes: every component is read from k0 and k1, which (with
// `motions`) must outlive what this returns.
LayeredKeyframes wholeKeyframes(const FrameImage& k0, const FrameImage& k1, const ComponentMotions& motions);

// interpolateFrameDetailed of the keyframes `keys` gives a component at a time.
InterpolationResult interpolateFrameDetailed(const LayeredKeyframes& keys, float s,
                                             const InterpolationSettings& settings = {});

// The frame of interpolateFrameDetailed.
FrameImage interpolateFrame(const FrameImage& k0, const FrameImage& k1, const ComponentMotions& motions, float s,
                            const InterpolationSettings& settings = {});

}  // namespace pathfarm
