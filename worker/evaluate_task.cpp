// The error figures of a shot's report (worker/filter_tasks.h): every stage output of the
// evaluation frames against their reference, as relMSE of the beauty, and the temporal
// error (relMSE of frame-to-frame differences) of the final frames and of the baseline.
#include <map>

#include "postproc/metrics/image_metrics.h"
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
      return "denoise";
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

}  // namespace

TaskOutput runEvaluateTask(const Lease& /*lease*/, const std::vector<TaskInput>& inputs) {
  std::map<int64_t, const FrameImage*> references;
  for (const TaskInput& input : inputs)
    if (input.kind == TASK_ASSEMBLE_FRAME && input.params.role() == ROLE_REFERENCE)
      references[input.params.frame()] = &input.image;
  if (references.empty()) throw std::runtime_error("the evaluation has no reference frame");

  std::map<std::string, std::pair<double, int>> sums;  // stage -> (sum of relMSE, frames)
  std::map<std::string, std::map<int64_t, const FrameImage*>> sequences;  // final, baseline
  for (const TaskInput& input : inputs) {
    const std::string stage = stageOf(input);
    const auto reference = references.find(input.params.frame());
    if (stage.empty() || reference == references.end()) continue;
    // A half-resolution denoise output has no full-resolution error; its upsampling has.
    if (input.image.width() != reference->second->width() || input.image.height() != reference->second->height())
      continue;
    auto& [sum, frames] = sums[stage];
    sum += compareImages(input.image, *reference->second, kBeauty).relMse;
    ++frames;
    if (stage == "final" || stage == "baseline") sequences[stage][input.params.frame()] = &input.image;
  }
  TaskOutput output;
  for (const auto& [stage, total] : sums) output.metrics["relmse." + stage] = total.first / total.second;
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
  // The chunk records the figures as text, one "name value" per line.
  for (const auto& [name, value] : output.metrics) output.chunk += name + " " + std::to_string(value) + "\n";
  return output;
}

}  // namespace pathfarm::farm
