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

// Sets every component's "<c>.irradiance.R/G/B" to the effective irradiance of its color and
// reflectance, as the renderer derives it: for a frame whose colors a filter changed.
// Throws std::invalid_argument naming a missing channel.
void deriveIrradiance(FrameImage& frame);

}  // namespace pathfarm
