#pragma once
// The channels an intermediate chunk of the filtering pipelines keeps: those the tasks that
// read it use, and no others. A decomposed render carries 29 channels per component (158
// with five components, 1.3 GB decoded at 1080p); which task reads which is the
// table in docs/farm.md, "Channels of the intermediate chunks". Every chunk keeps its
// attributes.
#include <optional>
#include <string>

#include "contract/pipeline.h"
#include "image/exr_io.h"
#include "image/frame_image.h"
#include "pathfarm/shot.pb.h"

namespace pathfarm::farm {

// What a chunk is, as far as its readers go.
enum class ChunkContent {
  KeyframeRender,          // a keyframe's tiles and frame: denoise, upsample, through them flow and interpolation
  FeatureRender,           // an in-between frame's tiles and frame: interpolation's checks
  RerenderedPixels,        // re-render tiles: the composite's denoise
  HalfResolutionDenoised,  // du, dui: the denoised keyframe the upsampler reads
  FilteredKeyframe,        // di's denoise, du's and dui's upsample output: the composite, flow, interpolation
};

// What a decomposed render tile of a filtering pipeline is for, by its role: nothing for the
// roles whose frames are not filtered (a reference, a baseline, pt's output), whose every
// channel is kept.
std::optional<ChunkContent> renderedContent(TaskRole role);

// Whether an upsample task reads a channel of its keyframe's render: what the upsampler
// reads and what its output passes on, less the irradiance the upsampled one replaces
// (not the variance and ids only the denoiser reads).
bool upsampleReads(const std::string& channel, FilteringStages stages);

// Whether the chunk's readers in `stages` read any motion (a component's or the frame's
// motion, or its silhouettes): a render tile of a chunk without skips measuring it.
bool readsMotion(ChunkContent content, FilteringStages stages);

// Removes every channel of `frame` the chunk's readers in `stages` do not use.
void keepReadChannels(ChunkContent content, FilteringStages stages, FrameImage& frame);

// The channels of an intermediate chunk written as 16-bit floats (image/exr_io.h): the
// radiance (the beauty, a component's color, emission and irradiance) and the bounded
// features (reflectance, normal, coverage), each where all of its values in `frame` fit a
// half. A half errs by at most 2^-11 (0.05 %) of a value, where a filtered frame at any
// spp the farm renders errs by a percent or more (docs/performance.md, "Intermediate
// chunks in half floats"). The variance keeps 32 bits (the denoiser divides by it, and a
// dark pixel's lies below a half's normal range), and so do motion, depth and ids.
ChannelFilter halfPrecisionChannels(const FrameImage& frame);

}  // namespace pathfarm::farm
