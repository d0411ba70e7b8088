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
//               (exact match), `c.depth.Z` when DenoiseSettings::useDepth. The paper
//               prefilters noisy features; these are not prefiltered: the frames carry no
//               feature variance, and with none an NL-means prefilter averages only
//               patches equal to within about 1e-5 (it changed a denoised dolly frame by a
//               relMSE of 1e-16 and took 14 % of its denoise);
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
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "image/frame_image.h"
#include "postproc/filters/decomposed_frame.h"
#include "postproc/filters/firefly_spread.h"
#include "postproc/filters/nlmeans.h"
#include "postproc/filters/warp.h"

namespace pathfarm {

enum class DenoiseMode {
  Decomposition,                 // per component, effective irradiance and its features
  ColorOnly,                     // the beauty with the primary features (a baseline)
  DecompositionWithoutFeatures,  // per component, color weights only (a baseline)
};

// "decomposition", "color", "no-features"; parseDenoiseMode throws std::invalid_argument.
std::string denoiseModeName(DenoiseMode mode);
DenoiseMode parseDenoiseMode(const std::string& name);

// A window of rows denoised apart, as a filter task in windows does (a bug in these rows is
// the caller's: std::logic_error): the frames given hold rows of frames `frameHeight` rows tall (the current frame from row currentTop, each
// neighbour from its own), and only rows [first, end) of the frame are wanted. Given the
// rows denoiseReach and denoiseNeighbourRows name, those rows are the whole frame's bits.
// Whether a neighbour takes part is the whole frame's call (it does when some pixel warps
// validly onto it, neighbourLayersReaching), which the rows alone cannot make: the layers
// whose previous and next frame do are given (a component's name; "" the beauty).
struct DenoiseWindow {
  int frameHeight = 0;
  int first = 0, end = 0;
  int currentTop = 0, previousTop = 0, nextTop = 0;
  std::set<std::string> previousReached, nextReached;
};

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
  // Every frame's fireflies are clamped before NL-means, and their excess, spread over
  // their surface (firefly_spread.h), is added back as the mean over the frames.
  bool spreadFireflies = true;
  FireflySettings fireflies;
  // Only the sampled pixels of this area matter to the caller (nlmeans.h,
  // jointNlMeansOnContent and NlMeansSettings::validCentersOnly): the filter skips what no
  // such pixel compares. Pixels outside, and pixels without a sample, come out unspecified.
  std::optional<NlMeansArea> onlyWithin;
  // Rows denoised apart from the rest of their frame (DenoiseWindow).
  std::optional<DenoiseWindow> window;
  // Name the frames in error messages (their files, say).
  std::string label = "frame";
  std::string previousLabel = "previous frame";
  std::string nextLabel = "next frame";
};

// The denoised frame: R, G, B, and in the decomposition modes every component's filtered
// `c.color.R/G/B`; the attributes of `current` plus `pathfarm.denoise` (the mode and
// parameters) and `pathfarm.denoise_skipped`. `previous` and `next` may be null. With a
// window, its wanted rows alone, and the counts are theirs.
FrameImage denoiseFrame(const FrameImage& current, const FrameImage* previous, const FrameImage* next,
                        const DenoiseSettings& settings);

// The rows of the current frame a denoised row depends on, on either side: the search
// radius and patch, and the fireflies' reach (firefly_spread.h).
int denoiseReach(const DenoiseSettings& settings);

// The rows [first, end) of the neighbour that the rows of `current` a window's rows depend
// on (those within denoiseReach) warp from; {0, 0} when none.
std::pair<int, int> denoiseNeighbourRows(const FrameImage& current, NeighbourFrame neighbour,
                                         const DenoiseSettings& settings);

// The layers (component names; "" the beauty) of which some pixel of `rows` (rows
// [top, top + height) of a frame frameHeight rows tall) warps validly onto the neighbour.
std::set<std::string> neighbourLayersReaching(const FrameImage& rows, NeighbourFrame neighbour, int top,
                                              int frameHeight, const DenoiseSettings& settings);

}  // namespace pathfarm
