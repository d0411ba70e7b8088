// Denoising and upsampling of keyframes (worker/filter_tasks.h).
#include <algorithm>
#include <optional>
#include <stdexcept>
#include <string>

#include "contract/pipeline.h"
#include "image/exr_io.h"
#include "postproc/filters/component_denoiser.h"
#include "postproc/filters/component_upsampler.h"
#include "postproc/filters/decomposed_frame.h"
#include "postproc/filters/guided_upsample.h"
#include "postproc/interpolation/caustic_check.h"
#include "worker/chunk_channels.h"
#include "worker/direct_emission.h"
#include "worker/failure_class.h"
#include "worker/filter_inputs.h"
#include "worker/final_frame.h"

namespace pathfarm::farm {
namespace {

constexpr int kUpsampleFactor = 2;
// NL-means' variance cancellation for keyframes rendered at the shot's full spp (d, di):
// 1 subtracts exactly the expected squared difference of two equal means, where the
// paper's 4 also takes in differences of a few standard deviations. At full spp the
// filter's bias outweighs its leftover noise: on frame 11 of the suite's d scenes, 1
// gave 15 to 24 % less relMSE than 4 (docs/performance.md). Quarter-spp keyframes keep 4.
constexpr float kFullSampleCancellation = 1.0f;

// Pastes a filter's output over the frame whose features it was given, with the filter's
// record of what it did (its attributes named `record*`, e.g. pathfarm.denoise_skipped):
// FrameImage::paste moves pixels only.
void pasteFiltered(const FrameImage& filtered, const std::string& record, FrameImage& frame) {
  frame.paste(filtered, 0, 0);
  for (const auto& [key, value] : filtered.attributes())
    if (key.rfind(record, 0) == 0) frame.attributes()[key] = value;
}

}  // namespace

TaskOutput runDenoiseTask(const Lease& lease, std::vector<TaskInput>& inputs) {
  const int64_t frame = lease.params().frame();
  const bool upsample = stagesOf(lease.spec().pipeline()).upsample;
  const std::vector<int64_t> keyframes = keyframesOf(lease.spec());
  const auto at = std::find(keyframes.begin(), keyframes.end(), frame);
  if (at == keyframes.end()) throw BadInput("frame " + std::to_string(frame) + " is not a keyframe");

  // The keyframe's motion vectors reach its neighbouring keyframes (planner.h). Each frame
  // is reduced (its directly seen light out; with u, to half resolution, read a strip of
  // rows at a time) before the next is decoded: a 1080p keyframe is more than a gigabyte.
  FrameImage emission;
  const auto reduced = [&](int64_t keyframe, FrameImage* light) {
    TaskInput& input = inputOf(inputs, TASK_ASSEMBLE_FRAME, keyframe);
    if (!upsample) {
      FrameImage image = input.take();
      FrameImage taken = takeDirectEmission(image);
      if (light) *light = std::move(taken);
      return image;
    }
    // The light of a keyframe to upsample is not kept: the upsampler adds it back from the
    // full-resolution render.
    return reducedWithoutLight(input, lease.spec().width(), lease.spec().height(), kUpsampleFactor);
  };
  FrameImage current = reduced(frame, &emission);
  std::optional<FrameImage> previous, next;
  if (at != keyframes.begin()) previous = reduced(*(at - 1), nullptr);
  if (at + 1 != keyframes.end()) next = reduced(*(at + 1), nullptr);
  DenoiseSettings settings;
  settings.label = "keyframe " + std::to_string(frame);
  if (!upsample) settings.alpha = kFullSampleCancellation;
  const FrameImage denoised = denoiseFrame(current, previous ? &*previous : nullptr, next ? &*next : nullptr, settings);
  // d: the denoised frame is the shot's final frame, and no later task reads its features.
  if (lease.params().role() == ROLE_OUTPUT) {
    FrameImage final = finalColorsOf(denoised);
    addDirectEmission(final, emission);
    std::vector<uint8_t> nothingRerendered(final.pixelCount(), 0);
    return finishedFinalFrame(std::move(final), nothingRerendered, lease.spec().pipeline());
  }
  // The output keeps the keyframe's features and motion; its colors are the denoised ones
  // and its effective irradiance follows from them, as the upsampler and interpolation read it.
  pasteFiltered(denoised, "pathfarm.denoise", current);
  deriveIrradiance(current);
  // Upsampling adds the light back at full resolution (runUpsampleTask).
  if (!upsample) addDirectEmission(current, emission);
  keepReadChannels(upsample ? ChunkContent::HalfResolutionDenoised : ChunkContent::FilteredKeyframe,
                   stagesOf(lease.spec().pipeline()), current);
  TaskOutput output;
  output.frame = std::move(current);
  return output;
}

TaskOutput runUpsampleTask(const Lease& lease, std::vector<TaskInput>& inputs) {
  // The join of a keyframe upsampled in windows writes it a window at a time, never whole.
  if (joinsWindows(lease, inputs)) return joinedWithRerender(lease, inputs, "upsamples");
  const int64_t frame = lease.params().frame();
  const int width = lease.spec().width(), height = lease.spec().height();
  const FilteringStages stages = stagesOf(lease.spec().pipeline());
  const RowWindow rows = rowsOf(lease, "the upsample");
  const FrameRows wanted{rows.first, rows.end};
  UpsampleSettings settings;
  settings.guided.factor = kUpsampleFactor;
  // The rows the filters read around the wanted ones: the guided filter's strips and
  // windows, which reach farther than the checks of the render's light below.
  const FrameRows reads = guidedUpsampleReads(wanted, height, settings.guided);
  const int checksReach = std::max(causticCheckReach({}), kLightEdgeReach);
  if ((reads.first > 0 && wanted.first - reads.first < checksReach) ||
      (reads.end < height && reads.end - wanted.end < checksReach))
    throw std::logic_error("the upsample's checks reach beyond the rows the guided filter reads");
  settings.guided.firstRow = reads.first;
  settings.guided.onlyFirst = wanted.first;
  settings.guided.onlyEnd = wanted.end;
  const FrameImage low = inputOf(inputs, TASK_DENOISE, frame)
                             .part({{}, reads.first / kUpsampleFactor, reads.end / kUpsampleFactor});
  FrameImage high = inputOf(inputs, TASK_ASSEMBLE_FRAME, frame)
                        .part({[&](const std::string& name) { return upsampleReads(name, stages); }, reads.first,
                               reads.end});
  // A moving caustic spread by the half-resolution filtering is rendered again at full spp.
  const std::vector<uint8_t> caustics = movingCausticPixels(high);
  // The directly seen light is added back unfiltered from the keyframe's own render, which
  // has a quarter of the shot's samples: where it has an edge, that render's noise shows (a
  // pixel a lamp covers in part; a glossy highlight, whose light a rough mirror scatters at
  // random), so those pixels are rendered again at the shot's spp, as in an interpolated frame.
  const std::vector<uint8_t> lightEdges = directLightEdges(directEmissionOf(high), high);
  const FrameImage emission = takeDirectEmission(high);
  pasteFiltered(upsampleFrame(low, high, settings), "pathfarm.upsample", high);
  addDirectEmission(high, emission);
  if (wanted.first != reads.first || wanted.end != reads.end)
    high = high.crop(0, wanted.first - reads.first, width, wanted.end - wanted.first);
  std::vector<float>& flagged = high.channel("rerender.Y");
  std::vector<uint8_t> mask(flagged.size());
  const size_t skipped = static_cast<size_t>(wanted.first - reads.first) * static_cast<size_t>(width);
  size_t causticPixels = 0, edgePixels = 0;
  for (size_t p = 0; p < mask.size(); ++p) {
    causticPixels += caustics[skipped + p];
    edgePixels += lightEdges[skipped + p];
    if (caustics[skipped + p] || lightEdges[skipped + p]) flagged[p] = 1.0f;
    mask[p] = flagged[p] > 0.5f ? 1 : 0;
  }
  TaskOutput output;
  // A window's flags go to the re-render with the frame's, from the join.
  if (!lease.params().has_window()) requestRerender(lease.spec(), frame, mask, output);
  output.metrics["rerender_moving_caustics"] = static_cast<double>(causticPixels);
  output.metrics["rerender_light_edges"] = static_cast<double>(edgePixels);
  keepReadChannels(ChunkContent::FilteredKeyframe, stages, high);
  output.frame = std::move(high);
  return output;
}

}  // namespace pathfarm::farm
