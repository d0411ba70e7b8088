#pragma once
// Denoising of decomposed frames (Zimmer et al. 2015, Section 6): every path-space
// component is filtered on its own, as effective irradiance (color / reflectance, so
// textures are not blurred) with joint NL-means guided by the component's own features
// (normal, reflectance, object id, optionally depth), then multiplied by its reflectance
// again; the components add up to the denoised beauty. With neighbour frames the filter
// is spatio-temporal: each component's buffers of the previous and next frames are warped
// onto the current frame along that component's motion.
//
// Per component c of the frame's `pathfarm.decomposition` attribute:
//   filtered:   `c.irradiance.R/G/B`, with the variance of the pixel mean carried through
//               the division per channel: Var = `c.variance` / reflectance^2 where
//               reflectance >= kReflectanceGuard, else `c.variance` itself; where
//               filterCoverage gives `c.coverage.Y`, both per covered area (perCoveredArea:
//               / share and / share^2), so a silhouette pixel's light reads as its neighbours';
//   features:   `c.normal.X/Y/Z`, `c.reflectance.R/G/B` (continuous), `c.objectid.Y`
//               (exact match), `c.depth.Z` when DenoiseSettings::useDepth. Continuous
//               features are prefiltered with NL-means (DenoiseSettings::prefilter; their
//               variance is zero, as the frames carry none, so the prefilter only averages
//               identical patches) in their own frame before being warped;
//   neighbours: the previous frame warped along `c.motion_back`, the next along `c.motion`,
//               both invalid where `c.motion_valid` is 0 or the source leaves the image;
//               ids warp by nearest pixel, everything else bilinearly (the variance too: an
//               overestimate of the interpolated value's variance). A neighbour with no
//               valid pixel is dropped, and a component that keeps no neighbour is filtered
//               spatially with the spatial radius;
//   output:     `c.color.R/G/B` = modulateIrradiance(filtered, `c.reflectance`), times
//               the pixel's own coverageShare where the coverage was divided out, and
//               R, G, B = the sum over the components.
// A component whose irradiance and variance are zero everywhere (no glass: no
// transmission) stays zero without being filtered.
//
// Baselines through the same code: ColorOnly filters the beauty R, G, B with `variance.*`
// and the primary features (those of `diffuse_direct`, else of the first component; none
// for a frame without decomposition), warped along the frame-wide `motion_back` /
// `motion`; DecompositionWithoutFeatures filters every component with color weights only.
//
// Broken input: a missing channel throws std::invalid_argument naming the frame's label and
// the channel (`frame.exr: missing channel "reflection.normal.X"`), as do frames of
// different sizes and a decomposition mode on a frame without `pathfarm.decomposition`.
// Non-finite colors or variances are invalid pixels (see nlmeans.h): they never
// contribute, and the current frame's are replaced by the filtered value of their valid
// neighbours; the number of such pixels (over all components) is the output's
// `pathfarm.denoise_skipped` attribute. The current frame's fireflies, spread instead of
// filtered (firefly_spread.h), are counted in `pathfarm.denoise_fireflies`. A non-finite
// reflectance modulates as 0 (the guard: the filtered irradiance is the color).
#include <optional>
#include <string>
#include <vector>

#include "image/frame_image.h"
#include "postproc/filters/decomposed_frame.h"
#include "postproc/filters/firefly_spread.h"
#include "postproc/filters/nlmeans.h"

namespace pathfarm {

enum class DenoiseMode {
  Decomposition,                 // per component, effective irradiance and its features
  ColorOnly,                     // the beauty with the primary features (a baseline)
  DecompositionWithoutFeatures,  // per component, color weights only (a baseline)
};

// "decomposition", "color", "no-features"; parseDenoiseMode throws std::invalid_argument.
std::string denoiseModeName(DenoiseMode mode);
DenoiseMode parseDenoiseMode(const std::string& name);

struct DenoiseSettings {
  DenoiseMode mode = DenoiseMode::Decomposition;
  int spatialRadius = 10;  // r when only the current frame is filtered
  int temporalRadius = 5;  // r when a neighbour frame contributes
  int patch = 3;           // f
  float kc = 0.45f;
  float kf = 0.6f;
  float tau = 0.001f;
  float alpha = 4.0f;     // variance cancellation (nlmeans.h)
  bool useDepth = false;  // `c.depth.Z` as a fourth feature
  bool prefilterFeatures = true;
  NlMeansSettings prefilter{.radius = 1, .patch = 3, .kc = 0.45f, .kf = 0.6f, .tau = 0.001f, .alpha = 4.0f};
  // Every frame's fireflies are clamped before NL-means, and their excess, spread over
  // their surface (firefly_spread.h), is added back as the mean over the frames.
  bool spreadFireflies = true;
  FireflySettings fireflies;
  // Only the sampled pixels of this area matter to the caller (nlmeans.h,
  // jointNlMeansOnContent and NlMeansSettings::validCentersOnly): the filter skips what no
  // such pixel compares. Pixels outside, and pixels without a sample, come out unspecified.
  std::optional<NlMeansArea> onlyWithin;
  // Name the frames in error messages (their files, say).
  std::string label = "frame";
  std::string previousLabel = "previous frame";
  std::string nextLabel = "next frame";
};

// The denoised frame: R, G, B, and in the decomposition modes every component's filtered
// `c.color.R/G/B`; the attributes of `current` plus `pathfarm.denoise` (the mode and
// parameters) and `pathfarm.denoise_skipped`. `previous` and `next` may be null.
FrameImage denoiseFrame(const FrameImage& current, const FrameImage* previous, const FrameImage* next,
                        const DenoiseSettings& settings);

}  // namespace pathfarm
