// The error figures of a shot's report (worker/filter_tasks.h): every stage output of the
// evaluation frames against their reference, as relMSE of the beauty with the artifact
// measures (worst 16x16 tile, share of the error in the worst 1 % of pixels), and the
// temporal error (relMSE of frame-to-frame differences) of the final frames and of the
// baseline. A stage that flags pixels for re-rendering (upsample, interpolate) is measured
// on the pixels it keeps: the flagged ones hold best-effort values the re-render replaces.
// The reference's own noise (its expected relMSE from its variance) bounds what the
// figures can tell. The task's chunk is the contact sheet of the evaluation frames (PNG;
// contact_sheet.h).
#include <algorithm>
#include <map>

#include "image/png_preview.h"
#include "postproc/metrics/contact_sheet.h"
#include "postproc/metrics/image_metrics.h"
#include "postproc/metrics/relmse.h"
#include "worker/failure_class.h"
#include "worker/filter_inputs.h"

namespace pathfarm::farm {
namespace {

// The report's name for what an input shows; empty for inputs that are not compared.
std::string stageOf(const TaskInput& input) {
  switch (input.kind) {
    case TASK_ASSEMBLE_FRAME:
      switch (input.params.role()) {
        case ROLE_KEYFRAME:
          return "render";
        case ROLE_OUTPUT:
          return "final";
        case ROLE_BASELINE:
          return "baseline";
        default:
          return "";
      }
    case TASK_DENOISE:
      return input.params.role() == ROLE_OUTPUT ? "final" : "denoise";
    case TASK_UPSAMPLE:
      return "upsample";
    case TASK_INTERPOLATE:
      return "interpolate";
    case TASK_COMPOSITE:
    case TASK_POISSON_BLEND:
    case TASK_MLT_MERGE:
      return "final";
    default:
      return "";
  }
}

const std::vector<std::string> kBeauty = {"R", "G", "B"};

// The pixels a stage keeps: those upsampling or interpolation do not flag for re-rendering
// (`rerender.Y`), all of any other stage's (a final frame's `rerender.Y` marks the pixels
// that were re-rendered).
std::vector<uint8_t> keptPixels(const std::string& stage, const FrameImage& image) {
  std::vector<uint8_t> kept(image.pixelCount(), 1);
  if ((stage != "upsample" && stage != "interpolate") || !image.hasChannel("rerender.Y")) return kept;
  const std::vector<float>& flagged = image.channel("rerender.Y");
  for (size_t p = 0; p < kept.size(); ++p) kept[p] = flagged[p] > 0.5f ? 0 : 1;
  return kept;
}

struct StageSums {
  double relMse = 0, worstTile = 0, worstShare = 0, kept = 0;
  int frames = 0;
};

}  // namespace

TaskOutput runEvaluateTask(const Lease& /*lease*/, const std::vector<TaskInput>& inputs) {
  std::map<int64_t, const FrameImage*> references;
  for (const TaskInput& input : inputs)
    if (input.kind == TASK_ASSEMBLE_FRAME && input.params.role() == ROLE_REFERENCE)
      references[input.params.frame()] = &input.image();
  if (references.empty()) throw BadInput("the evaluation has no reference frame");

  std::map<std::string, StageSums> sums;
  std::map<std::string, std::map<int64_t, const FrameImage*>> sequences;  // final, baseline
  for (const TaskInput& input : inputs) {
    const std::string stage = stageOf(input);
    const auto reference = references.find(input.params.frame());
    if (stage.empty() || reference == references.end()) continue;
    // A half-resolution denoise output has no full-resolution error; its upsampling has.
    if (input.image().width() != reference->second->width() || input.image().height() != reference->second->height())
      continue;
    const std::vector<uint8_t> kept = keptPixels(stage, input.image());
    const ImageMetrics m = compareImages(input.image(), *reference->second, kBeauty, {}, &kept);
    StageSums& sum = sums[stage];
    sum.relMse += m.relMse;
    sum.worstTile = std::max(sum.worstTile, m.worstTileRelMse);
    sum.worstShare += m.worstPercentShare;
    sum.kept += static_cast<double>(std::count(kept.begin(), kept.end(), 1)) / static_cast<double>(kept.size());
    ++sum.frames;
    if (stage == "final" || stage == "baseline") sequences[stage][input.params.frame()] = &input.image();
  }
  TaskOutput output;
  for (const auto& [stage, total] : sums) {
    output.metrics["relmse." + stage] = total.relMse / total.frames;
    output.metrics["worst_tile." + stage] = total.worstTile;  // the worst over the frames
    output.metrics["worst_share." + stage] = total.worstShare / total.frames;
    output.metrics["kept." + stage] = total.kept / total.frames;
  }
  for (const auto& [stage, frames] : sequences) {
    if (frames.size() < 2) continue;
    std::vector<FrameImage> images, referenced;
    for (const auto& [frame, image] : frames) {
      images.push_back(*image);
      referenced.push_back(*references.at(frame));
    }
    output.metrics["temporal." + stage] = compareSequences(images, referenced, kBeauty).temporalRelMse;
  }
  output.metrics["evaluation_frames"] = static_cast<double>(references.size());
  // The references' own expected relMSE, from their variance: the floor of the figures.
  double noise = 0;
  for (const auto& [frame, reference] : references) noise += expectedRelMse(*reference);
  output.metrics["reference_noise"] = noise / static_cast<double>(references.size());
  std::vector<ContactSheetRow> rows;
  for (const auto& [frame, reference] : references) {
    const auto& finals = sequences["final"];
    const auto& baselines = sequences["baseline"];
    const auto final = finals.find(frame);
    if (final == finals.end()) continue;
    const auto baseline = baselines.find(frame);
    rows.push_back({final->second, baseline == baselines.end() ? nullptr : baseline->second, reference});
  }
  output.chunk = rows.empty() ? std::string("no final frame among the evaluation frames\n")
                              : encodePngPreview(contactSheet(rows));
  return output;
}

}  // namespace pathfarm::farm
