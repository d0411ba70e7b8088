#pragma once
// Directly seen light is kept out of the filters. Light that reaches the camera with no
// diffuse vertex on its path (an emitter or the sky seen directly, in a mirror or through
// glass: Zimmer's E S* L paths) carries no Monte Carlo noise beyond the pixel's coverage,
// and its edges are the sharpest in the frame: denoising blurs them, after 2x2
// downsampling no guide feature restores them, and a component with no diffuse vertex has
// no features for the upsampler or the interpolation to follow. So every component's
// directly seen light (its `emission` buffer, renderer/decomposition/path_decomposer.h) is
// taken out before filtering, the rest is filtered, and the light is added back at full
// resolution; an interpolated frame gets the light of its own feature render, and an
// upsampled keyframe that of its quarter-spp render, whose few samples leave the edges of
// what is directly seen noisy (a pixel a lamp or the sky covers in part; a glossy lobe
// below the roughness threshold counts as specular and scatters a highlight at random):
// those edges are re-rendered at the shot's spp (directLightEdges).
#include <cstdint>
#include <string>
#include <vector>

#include "image/frame_image.h"

namespace pathfarm {

// Removes every component's directly seen light from the frame's beauty and that
// component's color (and irradiance, when the frame has it) and returns it as
// `<component>.direct.R/G/B`.
FrameImage takeDirectEmission(FrameImage& frame);
// The light takeDirectEmission would take, leaving the frame as it is.
FrameImage directEmissionOf(const FrameImage& frame);
// One component's part of it, from a frame that holds the component's color and emission.
FrameImage directEmissionOf(const FrameImage& frame, const std::string& component);

// takeDirectEmission a component at a time, for a task that holds a frame in parts: out of
// the component's color (and irradiance) in a part holding the component, and out of the
// beauty in a part holding `R`, `G`, `B` (`emission`: the component's, directEmissionOf).
// Taken from every component and the beauty, in the frame's component order, the same bits
// as takeDirectEmission.
void takeComponentEmission(FrameImage& frame, const std::string& component);
void takeFromBeauty(FrameImage& beauty, const FrameImage& emission, const std::string& component);
// Adds it back to the beauty and the components' colors (and irradiance, recomputed),
// at every pixel or only where `only` is set.
void addDirectEmission(FrameImage& frame, const FrameImage& emission, const std::vector<uint8_t>* only = nullptr);

// The pixels on either side of an edge of the directly seen light: where the luminance of
// the light (summed over components) differs from an 8-neighbour's by more than
// `significance` times the larger of the two pixels' beauty luminance. `beauty` is the
// frame the light was taken from.
std::vector<uint8_t> directLightEdges(const FrameImage& emission, const FrameImage& beauty, float significance = 0.05f);
// How many rows away directLightEdges reads (its 8-neighbours).
inline constexpr int kLightEdgeReach = 1;

}  // namespace pathfarm
