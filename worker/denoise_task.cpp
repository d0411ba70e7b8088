// Denoising of keyframes (worker/filter_tasks.h), whole or in windows of rows.
#include <algorithm>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

#include "contract/pipeline.h"
#include "postproc/filters/component_denoiser.h"
#include "postproc/filters/component_upsampler.h"
#include "postproc/filters/decomposed_frame.h"
#include "worker/chunk_channels.h"
#include "postproc/filters/direct_emission.h"
#include "worker/failure_class.h"
#include "worker/filter_inputs.h"
#include "worker/final_frame.h"

namespace pathfarm::farm {
namespace {

// NL-means' variance cancellation for keyframes rendered at the shot's full spp (d, di):
// 1 subtracts exactly the expected squared difference of two equal means, where the
// paper's 4 also takes in differences of a few standard deviations. At full spp the
// filter's bias outweighs its leftover noise: on frame 11 of the suite's d scenes, 1
// gave 15 to 24 % less relMSE than 4 (docs/performance.md). Quarter-spp keyframes keep 4.
constexpr float kFullSampleCancellation = 1.0f;
// Rows of a keyframe's motion read at a time to find which neighbours a window's
// components reach (denoised rows).
constexpr int kMotionStripRows = 64;
// The counts of the denoiser's record, summed over a frame's windows by their join.
const std::vector<std::string> kDenoiseCounts = {"pathfarm.denoise_skipped", "pathfarm.denoise_fireflies"};

bool isMotionChannel(const std::string& name) {
  return name.find(".motion") != std::string::npos || name.rfind("motion", 0) == 0;
}

// A keyframe's render as the denoiser takes it, rows [first, end) of the denoised frame:
// its directly seen light out (into `light` when given); with u at half resolution, read
// a strip of rows at a time (a 1080p keyframe is more than a gigabyte).
class KeyframeReader {
 public:
  KeyframeReader(const Lease& lease, std::vector<TaskInput>& inputs)
      : lease_(lease),
        inputs_(inputs),
        factor_(stagesOf(lease.spec().pipeline()).upsample ? kUpsampleFactor : 1),
        height_(lease.spec().height() / factor_) {}

  int factor() const { return factor_; }
  int height() const { return height_; }

  FrameImage rows(int64_t keyframe, int first, int end, FrameImage* light) const {
    TaskInput& input = inputOf(inputs_, TASK_ASSEMBLE_FRAME, keyframe);
    if (factor_ > 1)
      return reducedWithoutLight(input, lease_.spec().width(), lease_.spec().height(), factor_,
                                 {{}, first * factor_, end * factor_});
    FrameImage image = first == 0 && end == height_ ? input.take() : input.part({{}, first, end});
    FrameImage taken = takeDirectEmission(image);
    if (light) *light = std::move(taken);
    return image;
  }

  // Its motion channels alone, as rows() reduces them (the light is in no motion).
  FrameImage motionChannels(int64_t keyframe, int first, int end) const {
    const FrameImage rows =
        inputOf(inputs_, TASK_ASSEMBLE_FRAME, keyframe).part({isMotionChannel, first * factor_, end * factor_});
    return factor_ > 1 ? boxDownsample(rows, factor_) : rows;
  }

 private:
  const Lease& lease_;
  std::vector<TaskInput>& inputs_;
  int factor_, height_;
};

// Which layers of the keyframe reach each neighbour it has somewhere in the frame
// (DenoiseWindow): the whole frame's call, made from its motion a strip at a time, until
// every layer reaches every neighbour (mostly in the first strip).
void findLayersReaching(const KeyframeReader& reader, int64_t keyframe, bool previous, bool next,
                        DenoiseSettings& settings) {
  DenoiseWindow& window = *settings.window;
  size_t layers = 0;
  const auto done = [&] {
    return (!previous || window.previousReached.size() == layers) && (!next || window.nextReached.size() == layers);
  };
  for (int y = 0; y < reader.height(); y += kMotionStripRows) {
    const int end = std::min(reader.height(), y + kMotionStripRows);
    const FrameImage motion = reader.motionChannels(keyframe, y, end);
    layers = decompositionComponents(motion).size();
    if (previous)
      window.previousReached.merge(
          neighbourLayersReaching(motion, NeighbourFrame::Previous, y, reader.height(), settings));
    if (next)
      window.nextReached.merge(neighbourLayersReaching(motion, NeighbourFrame::Next, y, reader.height(), settings));
    if (done()) return;
  }
}

// The frames' join: the windows written one at a time, with the denoiser's counts summed.
TaskOutput joinedDenoise(const Lease& lease, std::vector<TaskInput>& inputs) {
  const bool final = lease.params().role() == ROLE_OUTPUT;
  const std::string label = "frame " + std::to_string(lease.params().frame());
  TaskOutput output;
  const JoinedWindows windows = joinRowWindows(
      lease, inputs, "denoises",
      [final, label](const FrameImage& rows) {
        if (final) requireFinalColors(rows, label);
      },
      output, {.flagged = final, .factor = stagesOf(lease.spec().pipeline()).upsample ? kUpsampleFactor : 1});
  std::map<std::string, std::string> record = summedCounts(windows, kDenoiseCounts, "the denoise of " + label);
  // d: the shot's frame, which nothing re-renders.
  if (final) {
    output.compression = ExrCompression::Small;
    recordRerender(record, 0, lease.spec().pipeline(), output);
  }
  addJoinedAttributes(output, std::move(record));
  return output;
}

}  // namespace

TaskOutput runDenoiseTask(const Lease& lease, std::vector<TaskInput>& inputs) {
  if (joinsWindows(lease, inputs)) return joinedDenoise(lease, inputs);
  const int64_t frame = lease.params().frame();
  const FilteringStages stages = stagesOf(lease.spec().pipeline());
  const std::vector<int64_t> keyframes = keyframesOf(lease.spec());
  const auto at = std::find(keyframes.begin(), keyframes.end(), frame);
  if (at == keyframes.end()) throw BadInput("frame " + std::to_string(frame) + " is not a keyframe");
  const KeyframeReader reader(lease, inputs);
  const RowWindow wanted = rowsOf(lease, "the denoise");
  if (wanted.first % reader.factor() != 0 || wanted.end % reader.factor() != 0)
    throw BadInput("the denoise of frame " + std::to_string(frame) + " to upsample is not of whole pairs of rows");
  // The keyframe's motion vectors reach its neighbouring keyframes (planner.h).
  const std::optional<int64_t> previousKeyframe =
      at != keyframes.begin() ? std::optional<int64_t>(*(at - 1)) : std::nullopt;
  const std::optional<int64_t> nextKeyframe =
      at + 1 != keyframes.end() ? std::optional<int64_t>(*(at + 1)) : std::nullopt;

  DenoiseSettings settings;
  settings.label = "keyframe " + std::to_string(frame);
  if (!stages.upsample) settings.alpha = kFullSampleCancellation;
  // A window reads the rows its filter reaches: of its keyframe around its rows, of the
  // neighbours where those rows' motion leads, and the whole keyframe's motion, to tell
  // which neighbours take part.
  int currentFirst = 0, currentEnd = reader.height();
  if (lease.params().has_window()) {
    DenoiseWindow& window = settings.window.emplace();
    window.frameHeight = reader.height();
    window.first = wanted.first / reader.factor();
    window.end = wanted.end / reader.factor();
    currentFirst = std::max(0, window.first - denoiseReach(settings));
    currentEnd = std::min(reader.height(), window.end + denoiseReach(settings));
    window.currentTop = currentFirst;
    findLayersReaching(reader, frame, previousKeyframe.has_value(), nextKeyframe.has_value(), settings);
  }
  // Each frame is reduced (its directly seen light out; with u, to half resolution) before
  // the next is decoded.
  FrameImage emission;
  FrameImage current = reader.rows(frame, currentFirst, currentEnd, stages.upsample ? nullptr : &emission);
  const auto neighbour = [&](const std::optional<int64_t>& keyframe, NeighbourFrame which, int& top) {
    std::optional<FrameImage> rows;
    if (!keyframe) return rows;
    auto [first, end] = std::pair{0, reader.height()};
    if (settings.window) {
      std::tie(first, end) = denoiseNeighbourRows(current, which, settings);
      // No pixel of the window warps onto it: any row will do, none is read.
      if (first >= end) std::tie(first, end) = std::pair{0, 1};
    }
    top = first;
    rows = reader.rows(*keyframe, first, end, nullptr);
    return rows;
  };
  int previousTop = 0, nextTop = 0;
  const std::optional<FrameImage> previous = neighbour(previousKeyframe, NeighbourFrame::Previous, previousTop);
  const std::optional<FrameImage> next = neighbour(nextKeyframe, NeighbourFrame::Next, nextTop);
  if (settings.window) {
    settings.window->previousTop = previousTop;
    settings.window->nextTop = nextTop;
  }
  const FrameImage denoised = denoiseFrame(current, previous ? &*previous : nullptr, next ? &*next : nullptr, settings);
  // The rows computed, of what was read.
  const int keptFirst = settings.window ? settings.window->first - currentFirst : 0;
  const auto keptRows = [&](FrameImage image) {
    if (image.height() == denoised.height()) return image;
    return image.crop(0, keptFirst, image.width(), denoised.height());
  };
  // d: the denoised frame is the shot's final frame, and no later task reads its features.
  if (lease.params().role() == ROLE_OUTPUT) {
    FrameImage final = finalColorsOf(denoised);
    addDirectEmission(final, keptRows(std::move(emission)));
    std::vector<uint8_t> nothingRerendered(final.pixelCount(), 0);
    if (!settings.window) return finishedFinalFrame(std::move(final), nothingRerendered, lease.spec().pipeline());
    addRerenderMask(final, nothingRerendered);
    TaskOutput output;
    output.chunk = encodeExr(final, ExrCompression::Fast);
    return output;
  }
  // The output keeps the keyframe's features and motion; its colors are the denoised ones
  // and its effective irradiance follows from them, as the upsampler and interpolation read it.
  current = keptRows(std::move(current));
  pasteFiltered(denoised, "pathfarm.denoise", current);
  deriveIrradiance(current);
  // Upsampling adds the light back at full resolution (runUpsampleTask).
  if (!stages.upsample) addDirectEmission(current, keptRows(std::move(emission)));
  keepReadChannels(stages.upsample ? ChunkContent::HalfResolutionDenoised : ChunkContent::FilteredKeyframe, stages,
                   current);
  TaskOutput output;
  output.frame = std::move(current);
  return output;
}

}  // namespace pathfarm::farm
