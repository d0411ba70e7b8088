#pragma once
// Joint upsampling of a decomposed frame (Zimmer et al. 2015, Section 5.2): every
// path-space component's effective irradiance, rendered at low resolution, is upsampled by
// the guided filter under that component's full-resolution features, then modulated by the
// full-resolution reflectance, so textures and edges come from the features and only the
// smooth illumination is interpolated.
#include <string>
#include <vector>

#include "image/frame_image.h"
#include "postproc/filters/guided_upsample.h"

namespace pathfarm {

struct UpsampleSettings {
  GuidedUpsampleSettings guided;  // factor, radius (low-resolution pixels), epsilon, threads
  // The guide of component c: the channels of "<c>.<buffer>.*" in the full-resolution
  // features, for each buffer in this order (reflectance R G B, normal X Y Z, emission R G B).
  std::vector<std::string> guideBuffers = {"reflectance", "normal", "emission"};
  // A pixel is flagged for re-rendering when the color clamped away from its components'
  // negative upsampled irradiance (luminance, summed over the components) exceeds this
  // fraction of its beauty's luminance: a linear fit's slight undershoot near zero costs
  // no re-render, a real failure does.
  float significance = 0.02f;
};

// Upsamples a decomposed frame by settings.guided.factor.
//   low           the low-resolution render: attribute "pathfarm.decomposition"
//                 ("name=EXPR,...,residual"; the components are the names before '=' in
//                 order, then "residual") and, per component, "<c>.irradiance.R/G/B"
//   highFeatures  the full-resolution features, factor times larger: per component the
//                 guide buffers (by default "<c>.reflectance.R/G/B", "<c>.normal.X/Y/Z",
//                 "<c>.emission.R/G/B"); "<c>.reflectance.R/G/B" is always needed
// Where filterCoverage gives both frames' "<c>.coverage.Y", the irradiance upsampled is the
// light per covered area (perCoveredArea with the low frame's coverage), and the result's
// irradiance is that times the full-resolution pixel's share: a silhouette pixel keeps its
// own share of the light.
// The result (full resolution) holds, in this order: beauty "R","G","B" (the sum of the
// components), per component "<c>.color.R/G/B" = modulateIrradiance(upsampled irradiance,
// full-resolution reflectance) and "<c>.irradiance.R/G/B" (upsampled; 0 where the
// features' "<c>.normal.X/Y/Z" is (0, 0, 0): no sample found the component), and "rerender.Y":
// 1 where the components' upsampled irradiance came out significantly negative (see
// UpsampleSettings::significance; negative channels are set to 0 in any case). Attributes:
// those of `low`, "pathfarm.rerender_pixels" (the number of rerender pixels) and "pathfarm.upsample" (the method and settings). Feature channels are not
// copied; `FrameImage out = highFeatures; out.paste(result, 0, 0);` merges them.
// Throws std::invalid_argument naming the missing channel, or when the sizes do not fit
// the factor, or (from guidedUpsample) for settings out of range.
FrameImage upsampleFrame(const FrameImage& low, const FrameImage& highFeatures, const UpsampleSettings& settings);

// The evaluation protocol's low-resolution input: a target-resolution render (with 1/factor^2
// of the samples) averaged over factor x factor blocks, so that every channel reads as a
// render at the low resolution would have it. Every channel is the block's mean, except:
//   "<c>.reflectance.*"      with "<c>.coverage.Y", the mean weighed by coverage (the
//                            reflectance is a mean over the samples that reached the surface)
//   "<c>.irradiance.*"       recomputed as effectiveIrradiance(mean color, mean reflectance),
//                            as the renderer derives it (when "<c>.color.*" and
//                            "<c>.reflectance.*" exist; else the mean)
//   "variance.*", "<c>.variance.*"  mean / factor^2: the variance of the mean of factor^2
//                            independent pixel means
//   "<c>.normal.X/Y/Z"       the mean, renormalized (0 stays 0)
//   "*.objectid.Y", "*.primid.Y"  the block's top-left pixel (ids cannot be averaged)
//   "motion.*", "motion_back.*" and the components' ones: the mean / factor (low-resolution pixels)
//   "silhouette.Y", "*.motion_valid.Y"  the block's maximum
// Attributes are copied. Throws std::invalid_argument when factor < 1 or the size is not a
// multiple of the factor.
FrameImage boxDownsample(const FrameImage& high, int factor);

}  // namespace pathfarm
