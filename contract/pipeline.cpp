#include "contract/pipeline.h"

#include <algorithm>
#include <stdexcept>

#include "image/row_bands.h"

namespace pathfarm::farm {

const std::vector<PipelineTraits>& allPipelines() {
  using F = PipelineFamily;
  static const std::vector<std::string_view> filteringKeys = {"keyframe_interval", "rerender_bound", "feature_spp",
                                                              "filter_window_rows", "rerender_spp"};
  static const std::vector<std::string_view> gradientKeys = {"poisson_window", "poisson_overlap", "poisson_norm"};
  static const std::vector<std::string_view> metropolisKeys = {"mlt_window",       "mutations_per_pixel", "mlt_chains",
                                                               "chains_per_block", "chain_tasks",         "temporal_delta",
                                                               "tune_delta",       "bootstrap_samples"};
  static const std::vector<PipelineTraits> pipelines = {
      {PIPELINE_AUTO, "auto", F::Choice, "", {}, {}},
      {PIPELINE_PT, "pt", F::Plain, "pt", {}, {}},
      {PIPELINE_D, "d", F::Filtering, "pt", {false, false}, filteringKeys},
      {PIPELINE_DU, "du", F::Filtering, "pt", {true, false}, filteringKeys},
      {PIPELINE_DI, "di", F::Filtering, "pt", {false, true}, filteringKeys},
      {PIPELINE_DUI, "dui", F::Filtering, "pt", {true, true}, filteringKeys},
      {PIPELINE_TGPT, "tgpt", F::Gradient, "tgpt", {}, gradientKeys},
      {PIPELINE_PSSMLT, "pssmlt", F::Metropolis, "pssmlt", {}, metropolisKeys},
      {PIPELINE_MLT, "mlt", F::Metropolis, "mlt", {}, metropolisKeys},
      {PIPELINE_TMLT, "tmlt", F::Metropolis, "tmlt", {}, metropolisKeys},
      {PIPELINE_NOOP, "noop", F::Noop, "", {}, {"noop_tasks"}},
  };
  return pipelines;
}

namespace {

const PipelineTraits* findTraits(Pipeline pipeline) {
  const auto& pipelines = allPipelines();
  const auto found = std::find_if(pipelines.begin(), pipelines.end(), [&](const auto& p) { return p.pipeline == pipeline; });
  return found == pipelines.end() ? nullptr : &*found;
}

bool isOfFamily(Pipeline pipeline, PipelineFamily family) {
  const PipelineTraits* traits = findTraits(pipeline);
  return traits && traits->family == family;
}

}  // namespace

const PipelineTraits& traitsOf(Pipeline pipeline) {
  const PipelineTraits* traits = findTraits(pipeline);
  if (!traits) throw std::invalid_argument(pipelineLabel(pipeline) + ": no such pipeline");
  return *traits;
}

std::string pipelineLabel(Pipeline pipeline) {
  const PipelineTraits* traits = findTraits(pipeline);
  return traits ? std::string(traits->name) : "unknown pipeline " + std::to_string(pipeline);
}

std::string_view pipelineName(Pipeline pipeline) { return traitsOf(pipeline).name; }

std::optional<Pipeline> pipelineNamed(std::string_view name) {
  for (const PipelineTraits& traits : allPipelines())
    if (traits.name == name) return traits.pipeline;
  return std::nullopt;
}

std::string pipelineNames() {
  std::string names;
  for (const PipelineTraits& traits : allPipelines()) names += (names.empty() ? "" : ", ") + std::string(traits.name);
  return names;
}

bool isFilteringPipeline(Pipeline pipeline) { return isOfFamily(pipeline, PipelineFamily::Filtering); }

bool isMetropolisPipeline(Pipeline pipeline) { return isOfFamily(pipeline, PipelineFamily::Metropolis); }

FilteringStages stagesOf(Pipeline pipeline) {
  if (!isFilteringPipeline(pipeline))
    throw std::invalid_argument(pipelineLabel(pipeline) + " is not a filtering pipeline");
  return traitsOf(pipeline).stages;
}

int keyframeSppOf(const ShotSpec& spec) {
  return stagesOf(spec.pipeline()).upsample ? std::max(1, spec.spp() / 4) : spec.spp();
}

int rerenderSppOf(const ShotSpec& spec) {
  return spec.rerender_spp() > 0 ? std::min(spec.rerender_spp(), spec.spp()) : spec.spp();
}

std::vector<int64_t> keyframesOf(const ShotSpec& spec) {
  const int64_t step = stagesOf(spec.pipeline()).interpolate ? std::max(1, spec.keyframe_interval()) : 1;
  std::vector<int64_t> keyframes;
  for (int64_t frame = spec.frame_start(); frame <= spec.frame_end(); frame += step) keyframes.push_back(frame);
  if (keyframes.back() != spec.frame_end()) keyframes.push_back(spec.frame_end());
  return keyframes;
}

std::vector<RowWindow> filterWindowsOf(const ShotSpec& spec) {
  const int64_t rows = spec.filter_window_rows() > 0 ? spec.filter_window_rows() : kDefaultFilterWindowRows;
  std::vector<RowWindow> windows;
  for (const auto& [first, end] : evenRowBands(std::max(spec.height(), 1), rows)) windows.push_back({first, end});
  return windows;
}

}  // namespace pathfarm::farm
