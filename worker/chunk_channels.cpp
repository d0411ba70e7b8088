#include "worker/chunk_channels.h"

#include <set>
#include <string>
#include <string_view>

namespace pathfarm::farm {
namespace {

// The buffers a chunk keeps: every component's `perComponent` ("<c>.<buffer>.<channel>")
// and the frame-wide `frameWide` ("<buffer>.<channel>", or the beauty "R", "G", "B" as "").
struct Buffers {
  std::set<std::string_view> perComponent, frameWide;

  void add(const Buffers& more) {
    perComponent.insert(more.perComponent.begin(), more.perComponent.end());
    frameWide.insert(more.frameWide.begin(), more.frameWide.end());
  }

  bool keeps(std::string_view channel) const {
    const size_t first = channel.find('.');
    if (first == std::string_view::npos) return frameWide.count("") > 0;
    const size_t second = channel.find('.', first + 1);
    if (second == std::string_view::npos) return frameWide.count(channel.substr(0, first)) > 0;
    return perComponent.count(channel.substr(first + 1, second - first - 1)) > 0;
  }
};

// What the denoiser reads of a keyframe and of its neighbours (postproc/filters/
// component_denoiser.h; the beauty as the sum it replaces, the emission as the light it
// keeps out of the filter), and the composite of re-rendered pixels.
const Buffers kDenoised{{"color", "emission", "irradiance", "variance", "reflectance", "normal", "objectid", "coverage"},
                        {""}};
// Its motion along which the neighbours are warped.
const Buffers kDenoiseMotion{{"motion", "motion_back", "motion_valid"}, {}};
// What the upsampler reads of the full-resolution keyframe besides, and passes on.
const Buffers kUpsampled{{"color", "emission", "reflectance", "normal", "coverage"}, {"", "moving_caustic"}};
// What flow and interpolation read of a filtered keyframe (worker/interpolation_tasks.cpp).
const Buffers kInterpolated{{"color", "emission", "irradiance", "reflectance", "depth", "motion", "motion_back",
                             "motion_valid"},
                            {"", "depth", "motion", "motion_back", "silhouette"}};
// What the composite reads of a stage output, and the evaluation of its re-render mask.
const Buffers kComposited{{"color"}, {"", "rerender"}};
// What interpolation reads of an in-between frame's render: its reflectance, which
// modulates the interpolated irradiance, and what its checks compare (feature_check.h,
// radiance_check.h, the moving caustics and the directly seen light).
const Buffers kFeatures{{"color", "emission", "depth", "normal", "variance", "reflectance"},
                        {"", "moving_caustic", "variance"}};
// What the upsampler reads of the half-resolution denoised keyframe.
const Buffers kHalfResolution{{"irradiance", "coverage"}, {}};
// What a chunk may store as 16-bit floats (halfPrecisionChannels).
const Buffers kHalfPrecision{{"color", "emission", "irradiance", "reflectance", "normal", "coverage"}, {""}};

Buffers buffersOf(ChunkContent content, FilteringStages stages) {
  Buffers kept;
  switch (content) {
    case ChunkContent::KeyframeRender:
      kept.add(kDenoised);
      kept.add(kDenoiseMotion);
      if (stages.upsample) kept.add(kUpsampled);
      if (stages.interpolate) kept.add(kInterpolated);
      return kept;
    case ChunkContent::FeatureRender:
      return kFeatures;
    case ChunkContent::RerenderedPixels:
      return kDenoised;
    case ChunkContent::HalfResolutionDenoised:
      return kHalfResolution;
    case ChunkContent::FilteredKeyframe:
      kept.add(kComposited);
      if (stages.interpolate) kept.add(kInterpolated);
      return kept;
  }
  return kept;
}

}  // namespace

std::optional<ChunkContent> renderedContent(TaskRole role) {
  switch (role) {
    case ROLE_KEYFRAME:
      return ChunkContent::KeyframeRender;
    case ROLE_FEATURES:
      return ChunkContent::FeatureRender;
    case ROLE_RERENDER:
      return ChunkContent::RerenderedPixels;
    default:
      return std::nullopt;
  }
}

bool upsampleReads(const std::string& channel, FilteringStages stages) {
  Buffers read = buffersOf(ChunkContent::FilteredKeyframe, stages);
  read.add(kUpsampled);
  read.perComponent.erase("irradiance");
  return read.keeps(channel);
}

bool readsMotion(ChunkContent content, FilteringStages stages) {
  const Buffers read = buffersOf(content, stages);
  return read.perComponent.count("motion") > 0 || read.frameWide.count("motion") > 0 ||
         read.frameWide.count("silhouette") > 0;
}

void keepReadChannels(ChunkContent content, FilteringStages stages, FrameImage& frame) {
  const Buffers kept = buffersOf(content, stages);
  frame.removeChannels([&](const std::string& name) { return !kept.keeps(name); });
}

ChannelFilter halfPrecisionChannels(const FrameImage& frame) {
  std::set<std::string> half;
  for (const std::string& name : frame.channelNames())
    if (kHalfPrecision.keeps(name) && fitsHalf(frame.channel(name))) half.insert(name);
  return [half = std::move(half)](const std::string& name) { return half.count(name) > 0; };
}

}  // namespace pathfarm::farm
