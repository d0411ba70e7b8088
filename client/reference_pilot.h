#pragma once
// The pilot render of "reference_spp": "auto" (reference_choice.h): plain pt's relMSE per
// sample on one frame, from the variance of a small render.
#include <cstdint>

#include "pathfarm/shot.pb.h"

namespace pathfarm {
struct Scene;
}

namespace pathfarm::farm {

// The pilot renders at a quarter of the shot's resolution per axis with 16 times the
// samples per pixel: the cost of 8 spp at full size. A pixel's variance per sample hardly
// depends on its size (the paths' variance dominates the footprint's), and 8 samples a
// pixel miss the rare bright paths that make most of it: on the Cornell box an 8-spp pilot
// at full size put pt's relMSE at 1/7 of what a 128-spp reference then measured.
inline constexpr int kPilotScale = 4;
inline constexpr int kPilotSpp = 8 * kPilotScale * kPilotScale;

// pt's relMSE at one sample per pixel on `frame` of the spec's scene and size.
double pilotRelMsePerSample(const Scene& scene, const ShotSpec& spec, int64_t frame);

}  // namespace pathfarm::farm
