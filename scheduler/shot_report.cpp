#include "scheduler/shot_report.h"

#include <google/protobuf/util/json_util.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <initializer_list>
#include <map>
#include <set>

#include "image/atomic_file.h"
#include "scheduler/planner.h"
#include "scheduler/shot_verdict.h"

namespace pathfarm::farm {
namespace {

constexpr std::array<const char*, 7> kStages = {"render",    "denoise",     "upsample", "interpolate",
                                                "re-render", "reconstruct", "composite"};
constexpr const char* kMeasurement = "measurement";

// The stage a task's cost belongs to; the baseline, the reference and the evaluation are
// measurement, not part of the shot's cost.
std::string stageOf(const TaskRecord& task) {
  switch (task.kind) {
    case TASK_RENDER_TILE:
    case TASK_ASSEMBLE_FRAME:
      switch (task.params.role()) {
        case ROLE_RERENDER:
          return "re-render";
        case ROLE_BASELINE:
        case ROLE_REFERENCE:
          return kMeasurement;
        default:
          return "render";
      }
    case TASK_DENOISE:
      return "denoise";
    case TASK_UPSAMPLE:
      return "upsample";
    case TASK_FLOW:
    case TASK_INTERPOLATE:
      return "interpolate";
    case TASK_GRADIENT_RENDER:
    case TASK_GRADIENT_TILE:
    case TASK_MLT_SEED_POOL:
    case TASK_MLT_CHAINS:
      return "render";
    case TASK_POISSON_WINDOW:
      return "reconstruct";
    case TASK_COMPOSITE:
    case TASK_POISSON_BLEND:
    case TASK_MLT_MERGE:
      return "composite";
    default:
      return kMeasurement;
  }
}

double metric(const TaskRecord& task, const std::string& name) {
  const auto found = task.metrics.find(name);
  return found == task.metrics.end() ? 0.0 : found->second;
}

using CauseShares = google::protobuf::Map<std::string, double>;

// Adds the task's re-rendered pixels per cause (its "rerender_<cause>" metrics).
void addRerenderCauses(CauseShares& causes, const TaskRecord& task, std::initializer_list<const char*> names) {
  for (const char* cause : names) causes[cause] += metric(task, std::string("rerender_") + cause);
}

std::string format(const char* pattern, double value) {
  char text[64];
  std::snprintf(text, sizeof text, pattern, value);
  return text;
}

// What a shot's finished tasks add up to.
struct TaskTotals {
  std::map<std::string, StageCost> stages;
  double baselineSeconds = 0, interpolationRerender = 0, upsampleRerender = 0;
  double temporalProposed = 0, temporalAccepted = 0;
  int64_t interpolated = 0, upsampled = 0;
  std::set<std::pair<int64_t, int>> baselineRenders;  // (frame, repeat) of each assembled baseline
  std::map<std::string, double> errors;  // the evaluation task's figures
};

// Adds every done task's cost, samples and re-render counts to `report` and the totals.
TaskTotals addUpTasks(ShotReport& report, const std::vector<TaskRecord>& tasks) {
  TaskTotals totals;
  for (const TaskRecord& task : tasks) {
    if (!task.done) continue;
    report.set_tasks_done(report.tasks_done() + 1);
    const std::string stage = stageOf(task);
    if (stage == kMeasurement) {
      report.set_measurement_core_seconds(report.measurement_core_seconds() + task.coreSeconds);
    } else {
      StageCost& cost = totals.stages[stage];
      cost.set_tasks(cost.tasks() + 1);
      cost.set_core_seconds(cost.core_seconds() + task.coreSeconds);
      report.set_core_seconds(report.core_seconds() + task.coreSeconds);
    }
    if ((task.kind == TASK_RENDER_TILE || task.kind == TASK_GRADIENT_RENDER || task.kind == TASK_GRADIENT_TILE ||
         task.kind == TASK_MLT_CHAINS) &&
        stage != kMeasurement)
      report.set_samples_traced(report.samples_traced() + metric(task, "samples"));
    if (task.params.role() == ROLE_BASELINE) {
      totals.baselineSeconds += task.coreSeconds;
      if (task.kind == TASK_ASSEMBLE_FRAME && !task.params.has_window())  // a whole frame, not a region of one
        totals.baselineRenders.insert({task.params.frame(), task.params.baseline_repeat()});
    }
    // A frame filtered in windows of rows: each window counts its causes, the join the frame.
    if (task.kind == TASK_INTERPOLATE) {
      addRerenderCauses(*report.mutable_interpolation_rerender_causes(), task,
                        {"holes", "silhouettes", "untracked", "illumination", "mismatch", "light_edges", "light_mismatch",
                         "moving_caustics"});
      if (!task.params.has_window()) {
        totals.interpolationRerender += metric(task, "rerender_pixels");
        ++totals.interpolated;
      }
    }
    if (task.kind == TASK_UPSAMPLE) {
      addRerenderCauses(*report.mutable_upsample_rerender_causes(), task, {"moving_caustics", "light_edges"});
      if (!task.params.has_window()) {
        totals.upsampleRerender += metric(task, "rerender_pixels");
        ++totals.upsampled;
      }
    }
    if (task.kind == TASK_COMPOSITE)
      report.set_rerender_pixels(report.rerender_pixels() + static_cast<int64_t>(metric(task, "rerender_pixels")));
    if (task.kind == TASK_EVALUATE) totals.errors = task.metrics;
    totals.temporalProposed += metric(task, "temporal_proposed");
    totals.temporalAccepted += metric(task, "temporal_accepted");
  }
  return totals;
}

// Core-seconds per stage and frame, the baseline's, and what follows from them.
void setCosts(ShotReport& report, const ShotSpec& spec, const TaskTotals& totals) {
  const double frames = static_cast<double>(report.frames());
  const double pixels = static_cast<double>(spec.width()) * spec.height();
  for (const char* name : kStages) {
    if (!totals.stages.count(name)) continue;
    StageCost cost = totals.stages.at(name);
    cost.set_stage(name);
    cost.set_core_seconds_per_frame(cost.core_seconds() / frames);
    *report.add_stages() = cost;
  }
  report.set_core_seconds_per_frame(report.core_seconds() / frames);
  if (spec.pipeline() == PIPELINE_PT) {
    report.set_baseline_core_seconds_per_frame(report.core_seconds_per_frame());
    report.set_baseline_source("the shot itself: plain path tracing");
  } else if (spec.baseline_core_seconds() > 0) {
    report.set_baseline_core_seconds_per_frame(spec.baseline_core_seconds());
    report.set_baseline_source("given in the shot");
  } else if (!totals.baselineRenders.empty()) {
    const size_t renders = totals.baselineRenders.size();
    std::set<int64_t> frames;
    for (const auto& [frame, repeat] : totals.baselineRenders) frames.insert(frame);
    report.set_baseline_core_seconds_per_frame(totals.baselineSeconds / static_cast<double>(renders));
    report.set_baseline_source("measured: pt at " + std::to_string(spec.spp()) + " spp on " +
                               std::to_string(frames.size()) + " frame(s)" +
                               (renders > frames.size() ? ", " + std::to_string(renders) + " independent renders" : ""));
  } else {
    report.set_baseline_source("not measured yet");
  }
  if (report.samples_traced() > 0)
    report.set_resolution_gain(frames * pixels * spec.spp() / report.samples_traced());
  if (report.baseline_core_seconds_per_frame() > 0) {
    report.set_relative_cost(report.core_seconds_per_frame() / report.baseline_core_seconds_per_frame());
    report.set_overhead(report.relative_cost() * report.resolution_gain());
  }
}

void setRerenderRates(ShotReport& report, const ShotSpec& spec, const TaskTotals& totals) {
  const double frames = static_cast<double>(report.frames());
  const double pixels = static_cast<double>(spec.width()) * spec.height();
  report.set_rerender_rate(static_cast<double>(report.rerender_pixels()) / (frames * pixels));
  if (totals.interpolated > 0) {
    report.set_interpolation_rerender_rate(totals.interpolationRerender / (totals.interpolated * pixels));
    for (auto& [cause, share] : *report.mutable_interpolation_rerender_causes()) share /= totals.interpolated * pixels;
  }
  if (totals.upsampled > 0) {
    report.set_upsample_rerender_rate(totals.upsampleRerender / (totals.upsampled * pixels));
    for (auto& [cause, share] : *report.mutable_upsample_rerender_causes()) share /= totals.upsampled * pixels;
  }
}

// The evaluation task's figures per stage, and the temporal errors.
void setErrors(ShotReport& report, const std::map<std::string, double>& errors) {
  report.set_temporal_error(-1);
  report.set_baseline_temporal_error(-1);
  for (const char* stage : {"render", "denoise", "upsample", "interpolate", "final", "baseline"}) {
    const auto found = errors.find(std::string("relmse.") + stage);
    if (found == errors.end()) continue;
    StageError* error = report.add_errors();
    error->set_stage(stage);
    error->set_relmse(found->second);
    const auto figure = [&](const char* name) {
      const auto it = errors.find(std::string(name) + "." + stage);
      return it == errors.end() ? 0.0 : it->second;
    };
    error->set_worst_tile_relmse(figure("worst_tile"));
    error->set_worst_percent_share(figure("worst_share"));
    error->set_kept(errors.count(std::string("kept.") + stage) ? figure("kept") : 1.0);
    if (const auto truth = intervalFigure(errors, "truth", std::string(".") + stage)) *error->mutable_truth_error() = *truth;
    if (const auto tile = intervalFigure(errors, "worst_tile_truth", std::string(".") + stage))
      *error->mutable_worst_tile_truth_error() = *tile;
  }
  report.set_reference_noise(errors.count("reference_noise") ? errors.at("reference_noise") : -1);
  if (errors.count("temporal.final")) report.set_temporal_error(errors.at("temporal.final"));
  if (errors.count("temporal.baseline")) report.set_baseline_temporal_error(errors.at("temporal.baseline"));
  if (const auto temporal = intervalFigure(errors, "temporal_truth", ".final"))
    *report.mutable_temporal_truth_error() = *temporal;
  if (const auto temporal = intervalFigure(errors, "temporal_truth", ".baseline"))
    *report.mutable_baseline_temporal_truth_error() = *temporal;
}

}  // namespace

ShotReport buildReport(const ShotSummary& summary, const ShotSpec& spec, const std::vector<TaskRecord>& tasks) {
  ShotReport report;
  report.set_shot_id(summary.id());
  report.set_name(spec.name());
  report.set_state(summary.state());
  report.set_pipeline(pipelineLabel(spec.pipeline()));
  report.set_pipeline_reason(spec.pipeline_reason());
  report.set_predicted_core_seconds_per_frame(spec.predicted_core_seconds_per_frame());
  report.set_predicted_relmse(spec.predicted_relmse());
  report.set_probe_core_seconds(spec.probe_core_seconds());
  report.set_frames(spec.frame_end() - spec.frame_start() + 1);
  report.set_width(spec.width());
  report.set_height(spec.height());
  report.set_spp(spec.spp());
  const bool filtering = isFilteringPipeline(spec.pipeline());
  report.set_keyframes(filtering ? static_cast<int64_t>(keyframesOf(spec).size()) : report.frames());
  report.set_keyframe_interval(filtering ? spec.keyframe_interval() : 1);
  report.set_keyframe_reason(filtering ? spec.keyframe_reason() : "every frame is rendered");
  if (filtering && (stagesOf(spec.pipeline()).upsample || stagesOf(spec.pipeline()).interpolate))
    report.set_rerender_spp(rerenderSppOf(spec));
  report.set_tasks_total(static_cast<int64_t>(tasks.size()));
  report.set_reference_spp(spec.reference_spp());
  report.set_cached_references(spec.known_references_size());
  report.set_reference_reason(spec.reference_reason());
  for (const int64_t frame : spec.evaluation_frames()) report.add_evaluation_frames(frame);

  const TaskTotals totals = addUpTasks(report, tasks);
  report.set_temporal_acceptance(totals.temporalProposed > 0 ? totals.temporalAccepted / totals.temporalProposed : -1);
  setCosts(report, spec, totals);
  setRerenderRates(report, spec, totals);
  setErrors(report, totals.errors);
  judge(report, spec.pipeline(), totals.errors);
  return report;
}

std::string predictionSummary(const ShotReport& r) {
  if (!(r.predicted_core_seconds_per_frame() > 0)) return "";
  const auto off = [](double measured, double predicted) {
    return format("%+.0f%%", 100 * (measured / predicted - 1));
  };
  std::string text = "The probe predicted " + format("%.3f", r.predicted_core_seconds_per_frame()) +
                     " core-seconds per frame; the shot took " + format("%.3f", r.core_seconds_per_frame()) + " (" +
                     off(r.core_seconds_per_frame(), r.predicted_core_seconds_per_frame()) + "). ";
  const auto final = std::find_if(r.errors().begin(), r.errors().end(), [](const auto& e) { return e.stage() == "final"; });
  if (final != r.errors().end() && r.predicted_relmse() > 0) {
    const double measured = final->has_truth_error() ? final->truth_error().estimate() : final->relmse();
    text += "It predicted relMSE " + format("%.5f", r.predicted_relmse()) + "; the shot measured " +
            format("%.5f", measured) + (final->has_truth_error() ? " against the truth" : "") + " (" +
            off(measured, r.predicted_relmse()) + "). ";
  }
  const double shot = r.core_seconds();
  text += "The probe cost " + format("%.1f", r.probe_core_seconds()) + " core-seconds" +
          (shot > 0 ? ", " + format("%.1f%%", 100 * r.probe_core_seconds() / shot) + " of the shot's" : "") + ".";
  return text;
}

std::string reportJson(const ShotReport& full) {
  ShotReport report = full;
  report.clear_contact_sheet_png();  // written beside it as a PNG
  std::string json;
  google::protobuf::util::JsonPrintOptions options;
  options.add_whitespace = true;
  options.always_print_primitive_fields = true;
  options.preserve_proto_field_names = true;
  const auto status = google::protobuf::util::MessageToJsonString(report, &json, options);
  if (!status.ok()) throw std::runtime_error("cannot write the report as JSON: " + status.ToString());
  return json;
}

namespace {

// What a stage's row shows, in the report's words.
std::string stageMeaning(const std::string& stage) {
  static const std::map<std::string, std::string> meaning = {
      {"render", "keyframes as rendered (before filtering)"},
      {"denoise", "keyframes denoised"},
      {"upsample", "keyframes upsampled"},
      {"interpolate", "in-between frames interpolated"},
      {"final", "**final frames**"},
      {"baseline", "plain pt at the same spp"}};
  const auto found = meaning.find(stage);
  return found == meaning.end() ? stage : found->second;
}

// A row per re-render cause, under the rate it splits.
std::string causeRows(const CauseShares& causes) {
  std::string rows;
  for (const auto& [cause, share] : causes)
    rows += std::string("| &nbsp; of which ").append(cause) + " | " + format("%.2f%%", 100 * share) + " |\n";
  return rows;
}

}  // namespace

std::string reportMarkdown(const ShotReport& r) {
  std::string md = "# Shot " + std::to_string(r.shot_id()) + " \"" + r.name() + "\": speed against error\n\n";
  md += "Pipeline `" + r.pipeline() + "`" + (r.pipeline_reason().empty() ? "" : " (" + r.pipeline_reason() + ")") +
        ", " + std::to_string(r.frames()) + " frames at " + std::to_string(r.width()) +
        "x" + std::to_string(r.height()) + ", " + std::to_string(r.spp()) + " spp; state " + ShotState_Name(r.state()) +
        ", " + std::to_string(r.tasks_done()) + " of " + std::to_string(r.tasks_total()) + " tasks done.\n\n";
  if (!r.verdict().empty()) md += "**Verdict:** " + r.verdict() + "\n\n";
  if (const std::string prediction = predictionSummary(r); !prediction.empty())
    md += "**The probe against the shot:** " + prediction + "\n\n";
  md += "Keyframes: " + std::to_string(r.keyframes()) + " (" + r.keyframe_reason() + ").\n\n";
  md += "| stage | tasks | core-seconds | core-seconds per frame | share |\n| --- | ---: | ---: | ---: | ---: |\n";
  for (const StageCost& s : r.stages())
    md += "| " + s.stage() + " | " + std::to_string(s.tasks()) + " | " + format("%.2f", s.core_seconds()) + " | " +
          format("%.3f", s.core_seconds_per_frame()) + " | " +
          format("%.1f%%", r.core_seconds() > 0 ? 100.0 * s.core_seconds() / r.core_seconds() : 0.0) + " |\n";
  md += "| **total** | | " + format("%.2f", r.core_seconds()) + " | " + format("%.3f", r.core_seconds_per_frame()) +
        " | |\n\n";
  md += "| figure | value |\n| --- | ---: |\n";
  md += "| plain pt core-seconds per frame (" + r.baseline_source() + ") | " +
        format("%.3f", r.baseline_core_seconds_per_frame()) + " |\n";
  md += "| resolution gain (pixel-samples of pt / traced) | " + format("%.2f", r.resolution_gain()) + " |\n";
  md += "| overhead (relative cost x resolution gain) | " + format("%.2f", r.overhead()) + " |\n";
  md += "| **relative cost** (core-seconds per frame / pt's) | " + format("%.3f", r.relative_cost()) + " |\n";
  if (r.cost_at_equal_error() >= 0)
    md += "| **cost at equal error** (relative cost x error / pt's, against the truth; pt's taken to fall as 1/spp; "
          "95 % interval) | " + intervalText(r.cost_at_equal_error_interval(), "%.3f") + " |\n";
  md += "| re-render rate, all frames | " + format("%.2f%%", 100 * r.rerender_rate()) + " |\n";
  if (r.rerender_spp() > 0) md += "| re-render samples per pixel | " + std::to_string(r.rerender_spp()) + " |\n";
  md += "| re-render rate, interpolated frames | " + format("%.2f%%", 100 * r.interpolation_rerender_rate()) + " |\n";
  md += causeRows(r.interpolation_rerender_causes());
  md += "| re-render rate, upsampled keyframes | " + format("%.2f%%", 100 * r.upsample_rerender_rate()) + " |\n";
  md += causeRows(r.upsample_rerender_causes());
  if (r.temporal_acceptance() >= 0)
    md += "| temporal perturbations accepted | " + format("%.1f%%", 100 * r.temporal_acceptance()) + " |\n";
  md += "| measurement core-seconds (baseline, reference, evaluation; not in the cost) | " +
        format("%.2f", r.measurement_core_seconds()) + " |\n\n";
  if (r.errors().empty()) {
    md += "No error figures: the shot names no `reference_spp`.\n";
    return md;
  }
  if (!r.reference_reason().empty()) md += "The reference's samples: " + r.reference_reason() + ".\n\n";
  if (r.cached_references() > 0)
    md += "The references of " + std::to_string(r.cached_references()) + " evaluation frame(s) came from the "
          "reference cache: an earlier shot rendered them from the same scene files and settings.\n\n";
  md += "Errors against pt at " + std::to_string(r.reference_spp()) + " spp on frames";
  for (const int64_t frame : r.evaluation_frames()) md.append(" ").append(std::to_string(frame));
  md += " (relMSE of the beauty; the worst 16x16 tile and the share of the error in the worst 1 % of pixels "
        "show artifacts the mean hides):\n\n"
        "| stage | relMSE | against the truth (95 % interval) | worst tile | worst tile against the truth | error in worst 1 % "
        "| pixels measured |\n| --- | ---: | ---: | ---: | ---: | ---: | ---: |\n";
  for (const StageError& e : r.errors()) {
    const std::string measured = e.kept() < 1 ? format("%.1f%% (kept, not re-rendered)", 100 * e.kept()) : "all";
    const auto truth = [](bool has, const Interval& interval, const char* pattern) {
      return has ? intervalText(interval, pattern) : std::string("-");
    };
    md += "| " + stageMeaning(e.stage()) + " | " + format("%.5f", e.relmse()) + " | " +
          truth(e.has_truth_error(), e.truth_error(), "%.5f") + " | " + format("%.4f", e.worst_tile_relmse()) + " | " +
          truth(e.has_worst_tile_truth_error(), e.worst_tile_truth_error(), "%.4f") + " | " +
          format("%.0f%%", 100 * e.worst_percent_share()) + " | " + measured + " |\n";
  }
  md += "\n| figure | value |\n| --- | ---: |\n";
  if (r.reference_noise() >= 0)
    md += "| the reference's own noise (its expected relMSE, included in every relMSE above) | " +
          format("%.5f", r.reference_noise()) + " |\n";
  if (r.temporal_error() >= 0)
    md += "| temporal error, final | " + format("%.5f", r.temporal_error()) + " |\n";
  if (r.has_temporal_truth_error())
    md += "| temporal error against the truth's change, final (95 % interval) | " +
          intervalText(r.temporal_truth_error(), "%.5f") + " |\n";
  if (r.baseline_temporal_error() >= 0)
    md += "| temporal error, baseline pt | " + format("%.5f", r.baseline_temporal_error()) + " |\n";
  if (r.has_baseline_temporal_truth_error())
    md += "| temporal error against the truth's change, baseline pt (95 % interval) | " +
          intervalText(r.baseline_temporal_truth_error(), "%.5f") + " |\n";
  if (!r.contact_sheet_png().empty())
    md += "\n![contact sheet](contact_sheet.png)\n\nContact sheet, a row per evaluation frame: final, pt at " +
          std::to_string(r.spp()) + " spp, reference, and the per-pixel relMSE of the first two (black 1e-4 or less, "
          "red, yellow, white 1 or more).\n";
  return md;
}

void writeReportFiles(const ShotReport& report, const std::filesystem::path& folder) {
  std::filesystem::create_directories(folder);
  writeFileAtomically(folder / "report.json", reportJson(report));
  writeFileAtomically(folder / "report.md", reportMarkdown(report));
  if (!report.contact_sheet_png().empty()) writeFileAtomically(folder / "contact_sheet.png", report.contact_sheet_png());
}

}  // namespace pathfarm::farm
