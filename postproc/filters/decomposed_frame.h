#pragma once
// Reading a decomposed frame's layout: which components its `pathfarm.decomposition`
// attribute names (docs/decomposition.md).
#include <string>
#include <vector>

#include "image/frame_image.h"

namespace pathfarm {

// The components named by a frame's `pathfarm.decomposition` attribute
// ("diffuse_direct=ED,...,residual": the text before each '=', and `residual` once, last);
// empty for a frame without the attribute.
std::vector<std::string> decompositionComponents(const FrameImage& frame);

// Whether the frame's `pathfarm.specular_components` attribute ("reflection,transmission",
// Decomposition::isSpecular) names `component`: its features and depth are those of the
// surface beyond a mirror or glass, not of what the camera hits first, and its motion is
// the manifold walk's. False for a frame without the attribute.
bool isSpecularComponent(const FrameImage& frame, const std::string& component);

// Component c's "<c>.coverage.Y" where the filters should divide it out (perCoveredArea),
// else null: when the frame has no such channel, and for a component whose expression
// passes a transmission (T) before its first D vertex. Whether a path gets through glass
// is the sampler's choice between reflecting and refracting at every interface, so that
// coverage is noise all over the glass, not a silhouette. Multiplied back per pixel, it
// made the walkthrough's glass ball speckled and too bright (its worst tile, 0.068 against
// 0.033 without).
const std::vector<float>* filterCoverage(const FrameImage& frame, const std::string& component);

// Sets every component's "<c>.irradiance.R/G/B" to the effective irradiance of its color and
// reflectance, as the renderer derives it: for a frame whose colors a filter changed.
// Throws std::invalid_argument naming a missing channel.
void deriveIrradiance(FrameImage& frame);

}  // namespace pathfarm
