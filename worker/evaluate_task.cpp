// The error figures of a shot's report (worker/filter_tasks.h): every stage output of the
// evaluation frames against their reference, as relMSE of the beauty with the artifact
// measures (worst 16x16 tile, share of the error in the worst 1 % of pixels), and the
// temporal error (relMSE of frame-to-frame differences) of the final frames and of the
// baseline. A stage that flags pixels for re-rendering (upsample, interpolate) is measured
// on the pixels it keeps: the flagged ones hold best-effort values the re-render replaces.
// The reference's own noise (its expected relMSE from its variance) bounds what the
// figures can tell: each figure is also given against the truth, the reference's noise
// taken out pixel by pixel, with a 95 % interval (error_interval.h), and so is the final
// frames' error over the baseline's, which the cost at equal error scales by. The task's
// chunk is the contact sheet of the evaluation frames (PNG; contact_sheet.h).
#include <algorithm>
#include <cmath>
#include <map>

#include "image/png_preview.h"
#include "postproc/metrics/contact_sheet.h"
#include "postproc/metrics/error_interval.h"
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

// The contact sheet travels inside the report, one gRPC message of at most 8 MiB: a row
// for at most kSheetRows evaluation frames, evenly spaced, and at most kSheetPixels pixels
// (3 bytes each in the PNG, at worst).
constexpr size_t kSheetRows = 8;
constexpr size_t kSheetPixels = 2'000'000;

// At most `count` of `rows`, evenly spaced from the first to the last.
std::vector<ContactSheetRow> evenlySpaced(const std::vector<ContactSheetRow>& rows, size_t count) {
  if (rows.size() <= count) return rows;
  std::vector<ContactSheetRow> chosen;
  for (size_t i = 0; i < count; ++i) chosen.push_back(rows[i * (rows.size() - 1) / (count - 1)]);
  return chosen;
}

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

// An input of the evaluation and the pixels of it that are measured.
struct Measured {
  const FrameImage* image;
  std::vector<uint8_t> kept;
};

// A stage's renders of one frame: one, or the baseline's independent renders
// (ShotSpec.baseline_repeats) in the order of their samples.
using Renders = std::vector<Measured>;

// The inputs of an evaluation: the references by frame, each stage's renders by frame.
struct Evaluation {
  std::map<int64_t, const FrameImage*> references;
  std::map<std::string, std::map<int64_t, Renders>> stages;
};

Evaluation sortedInputs(const std::vector<TaskInput>& inputs) {
  Evaluation evaluation;
  for (const TaskInput& input : inputs)
    if (input.kind == TASK_ASSEMBLE_FRAME && input.params.role() == ROLE_REFERENCE)
      evaluation.references[input.params.frame()] = &input.image();
  if (evaluation.references.empty()) throw BadInput("the evaluation has no reference frame");
  for (const TaskInput& input : inputs) {
    const std::string stage = stageOf(input);
    const auto reference = evaluation.references.find(input.params.frame());
    if (stage.empty() || reference == evaluation.references.end()) continue;
    // A half-resolution denoise output has no full-resolution error; its upsampling has.
    if (input.image().width() != reference->second->width() || input.image().height() != reference->second->height())
      continue;
    Renders& renders = evaluation.stages[stage][input.params.frame()];
    const auto repeat = static_cast<size_t>(std::max(0, input.params.baseline_repeat()));
    if (renders.size() <= repeat) renders.resize(repeat + 1, {nullptr, {}});
    renders[repeat] = {&input.image(), keptPixels(stage, input.image())};
  }
  // Every frame of a stage has its renders 0 .. n - 1, the same n.
  for (const auto& [stage, frames] : evaluation.stages)
    for (const auto& [frame, renders] : frames)
      if (renders.size() != frames.begin()->second.size() ||
          std::any_of(renders.begin(), renders.end(), [](const Measured& m) { return m.image == nullptr; }))
        throw BadInput("the evaluation misses one of frame " + std::to_string(frame) + "'s " + stage + " renders");
  return evaluation;
}

// A figure and its interval as metrics NAME.STAGE, NAME_low.STAGE and NAME_high.STAGE; an
// unbounded end is left out, and so is the whole figure when its estimate is not a number
// (metrics are finite numbers; the scheduler refuses others).
void putInterval(TaskOutput& output, const std::string& name, const std::string& suffix, const Interval& interval) {
  if (!std::isfinite(interval.estimate)) return;
  output.metrics[name + suffix] = interval.estimate;
  if (std::isfinite(interval.low)) output.metrics[name + "_low" + suffix] = interval.low;
  if (std::isfinite(interval.high)) output.metrics[name + "_high" + suffix] = interval.high;
}

// The contract's relMSE against the reference as it is, with the artifact measures.
void putRawFigures(const Evaluation& evaluation, TaskOutput& output) {
  for (const auto& [stage, frames] : evaluation.stages) {
    StageSums sum;
    for (const auto& [frame, renders] : frames) {
      // A frame's figures are its renders' average (only a baseline has several).
      const auto n = static_cast<double>(renders.size());
      double worstTile = 0;
      for (const Measured& measured : renders) {
        const ImageMetrics m =
            compareImages(*measured.image, *evaluation.references.at(frame), kBeauty, {}, &measured.kept);
        sum.relMse += m.relMse / n;
        worstTile += m.worstTileRelMse / n;
        sum.worstShare += m.worstPercentShare / n;
        sum.kept += static_cast<double>(std::count(measured.kept.begin(), measured.kept.end(), 1)) /
                    static_cast<double>(measured.kept.size()) / n;
      }
      sum.worstTile = std::max(sum.worstTile, worstTile);
      ++sum.frames;
    }
    output.metrics["relmse." + stage] = sum.relMse / sum.frames;
    output.metrics["worst_tile." + stage] = sum.worstTile;  // the worst over the frames
    output.metrics["worst_share." + stage] = sum.worstShare / sum.frames;
    output.metrics["kept." + stage] = sum.kept / sum.frames;
  }
}

// A frame's error terms against its reference, averaged over the stage's renders of it.
BlockedTerms frameTerms(const Renders& renders, const FrameImage& reference) {
  std::vector<BlockedTerms> each;
  for (const Measured& measured : renders) each.push_back(errorTerms(measured.image, reference, &measured.kept));
  return averageOf(each);
}

// A frame's worst-tile candidates, each tile's terms averaged over the renders. Only a
// baseline frame has several, and a baseline keeps every pixel, so their tiles are the
// same ones.
std::vector<BlockedTerms> frameTileTerms(const Renders& renders, const FrameImage& reference) {
  std::vector<std::vector<BlockedTerms>> each;
  for (const Measured& measured : renders) each.push_back(tileTerms(*measured.image, reference, &measured.kept));
  std::vector<BlockedTerms> tiles;
  for (size_t t = 0; t < each.front().size(); ++t) {
    std::vector<BlockedTerms> tile;
    for (const auto& render : each) tile.push_back(render.at(t));
    tiles.push_back(averageOf(tile));
  }
  return tiles;
}

// Each stage's error against the truth (the reference's noise taken out) with its interval,
// and its worst tile's.
void putTruthFigures(const Evaluation& evaluation, TaskOutput& output) {
  for (const auto& [stage, frames] : evaluation.stages) {
    BlockedTerms all;
    std::vector<BlockedTerms> tiles;
    for (const auto& [frame, renders] : frames) {
      const FrameImage& reference = *evaluation.references.at(frame);
      all.append(frameTerms(renders, reference));
      for (BlockedTerms& tile : frameTileTerms(renders, reference)) tiles.push_back(std::move(tile));
    }
    if (!all.sums.empty()) putInterval(output, "truth", "." + stage, meanInterval(all));
    if (!tiles.empty()) putInterval(output, "worst_tile_truth", "." + stage, maxOfMeansInterval(tiles));
  }
}

// The temporal error of the final frames and of the baseline: as the contract measures it
// against the reference, and against the truth's change with its interval; for the
// baseline's independent renders, the n-th render of each frame is a sequence, and the
// figures are their sequences' average.
void putTemporalFigures(const Evaluation& evaluation, TaskOutput& output) {
  for (const char* stage : {"final", "baseline"}) {
    const auto found = evaluation.stages.find(stage);
    if (found == evaluation.stages.end() || found->second.size() < 2) continue;
    const size_t sequences = found->second.begin()->second.size();
    double temporalRelMse = 0;
    std::vector<BlockedTerms> changes(sequences);
    for (size_t n = 0; n < sequences; ++n) {
      std::vector<FrameImage> images, referenced;
      const FrameImage* before = nullptr;
      int64_t frameBefore = 0;
      for (const auto& [frame, renders] : found->second) {
        const FrameImage& image = *renders.at(n).image;
        images.push_back(image);
        referenced.push_back(*evaluation.references.at(frame));
        if (before)
          changes[n].append(temporalTerms(*before, image, *evaluation.references.at(frameBefore),
                                          *evaluation.references.at(frame)));
        before = &image;
        frameBefore = frame;
      }
      temporalRelMse += compareSequences(images, referenced, kBeauty).temporalRelMse / static_cast<double>(sequences);
    }
    output.metrics[std::string("temporal.") + stage] = temporalRelMse;
    putInterval(output, "temporal_truth", std::string(".") + stage, meanInterval(averageOf(changes)));
  }
}

// The final frames' error over the baseline's, on the frames both have, with its interval
// (the blocks resampled together): what the cost at equal error scales the relative cost by.
void putErrorRatio(const Evaluation& evaluation, TaskOutput& output) {
  const auto finals = evaluation.stages.find("final"), baselines = evaluation.stages.find("baseline");
  if (finals == evaluation.stages.end() || baselines == evaluation.stages.end()) return;
  BlockedTerms final, baseline;
  for (const auto& [frame, renders] : finals->second) {
    const auto pt = baselines->second.find(frame);
    if (pt == baselines->second.end()) continue;
    const FrameImage& reference = *evaluation.references.at(frame);
    final.append(errorTerms(renders.front().image, reference));
    baseline.append(frameTerms(pt->second, reference));
  }
  // Both are measured over the same pixels unless one skipped a value that is not finite.
  if (!final.sums.empty() && final.counts == baseline.counts)
    putInterval(output, "error_ratio", "", ratioInterval(final, baseline));
}

}  // namespace

TaskOutput runEvaluateTask(const Lease& /*lease*/, std::vector<TaskInput>& inputs) {
  const Evaluation evaluation = sortedInputs(inputs);
  TaskOutput output;
  putRawFigures(evaluation, output);
  putTruthFigures(evaluation, output);
  putTemporalFigures(evaluation, output);
  putErrorRatio(evaluation, output);
  const auto& references = evaluation.references;
  output.metrics["evaluation_frames"] = static_cast<double>(references.size());
  // The references' own expected relMSE, from their variance: the floor of the figures.
  double noise = 0;
  for (const auto& [frame, reference] : references) noise += expectedRelMse(*reference);
  output.metrics["reference_noise"] = noise / static_cast<double>(references.size());
  std::vector<ContactSheetRow> rows;
  const auto finals = evaluation.stages.find("final"), baselines = evaluation.stages.find("baseline");
  for (const auto& [frame, reference] : references) {
    if (finals == evaluation.stages.end()) break;
    const auto final = finals->second.find(frame);
    if (final == finals->second.end()) continue;
    const FrameImage* baseline = nullptr;
    if (baselines != evaluation.stages.end()) {
      const auto pt = baselines->second.find(frame);
      if (pt != baselines->second.end()) baseline = pt->second.front().image;
    }
    rows.push_back({final->second.front().image, baseline, reference});
  }
  ContactSheetSettings sheet;
  sheet.maxPixels = kSheetPixels;
  output.chunk = rows.empty() ? std::string("no final frame among the evaluation frames\n")
                              : encodePngPreview(contactSheet(evenlySpaced(rows, kSheetRows), sheet));
  return output;
}

}  // namespace pathfarm::farm
