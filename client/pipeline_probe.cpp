#include "client/pipeline_probe.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "image/exr_io.h"
#include "postproc/metrics/relmse.h"
#include "client/pipeline_choice.h"
#include "client/reference_choice.h"
#include "client/shot_preparation.h"

namespace pathfarm::farm {
namespace {

// The shot read as each candidate, its scene as uploaded. A dui shot whose keyframe probe
// chose k = 1 reads as d, and di with k = 1 interpolates nothing: both are d, probed once.
std::vector<ShotSpec> candidateSpecs(const ShotFile& file, const ShotSpec& autoSpec) {
  std::vector<ShotSpec> specs;
  for (const Pipeline pipeline : autoCandidates()) {
    ShotSpec spec = preparedShot(file, pipeline);
    spec.set_scene(autoSpec.scene());
    *spec.mutable_inputs() = autoSpec.inputs();
    if (spec.pipeline() == PIPELINE_DI && spec.keyframe_interval() == 1) continue;
    const bool probed = std::any_of(specs.begin(), specs.end(), [&](const ShotSpec& s) {
      return s.pipeline() == spec.pipeline();
    });
    if (!probed) specs.push_back(std::move(spec));
  }
  return specs;
}

// The frames a finished probe shot of crop `window` wrote, added to `frames` under
// "<window>/<file name>".
void fetchFrames(FarmClient& client, int64_t id, size_t window, const std::filesystem::path& folder,
                 std::map<std::string, FrameImage>& frames) {
  for (const auto& file : client.fetch(id, folder))
    frames.emplace(std::to_string(window) + "/" + file.filename().string(), readExr(file));
}

// The candidate's relMSE against the truth over the frames plain pt's independent render
// stands in for (ProbeGeometry's measured frames), estimated against them; for pt itself,
// their own noise.
MeanEstimate estimatedRelMse(const std::map<std::string, FrameImage>& frames,
                             const std::map<std::string, FrameImage>& truthStandIn, bool isStandIn) {
  MeanEstimate estimate;
  for (const auto& [name, standIn] : truthStandIn) {
    if (isStandIn) {
      estimate += ownRelMseFromVariance(standIn);
      continue;
    }
    const auto frame = frames.find(name);
    if (frame == frames.end()) throw std::runtime_error("the probe has no " + name);
    estimate += relMseLessReferenceNoise(frame->second, standIn);
  }
  return estimate;
}

// Submits every candidate's probe shots of `round`, one per crop; returns their ids, in
// the candidates' order and then the crops'.
std::vector<std::vector<int64_t>> submitProbes(FarmClient& client, const std::vector<ShotSpec>& candidates,
                                               const ProbeGeometry& geometry, const std::filesystem::path& probeFolder,
                                               const std::string& submitKey, ProbeRound round) {
  std::vector<std::vector<int64_t>> ids;
  std::string names;
  for (const ShotSpec& candidate : candidates) {
    const std::string name(pipelineName(candidate.pipeline()));
    ids.emplace_back();
    for (size_t window = 0; window < geometry.windows.size(); ++window) {
      const ShotSpec probe = probeSpecOf(candidate, geometry, window, probeFolder, round);
      // The probe's name extends the shot's, so it keys the resubmission alike.
      const std::string key = submitKey.empty() ? "" : submitKey + probe.name().substr(candidate.name().size());
      ids.back().push_back(client.submit(probe, key));
    }
    names += (names.empty() ? "" : ", ") + name;
  }
  spdlog::info("pipeline auto: probing {} on frames {}..{}, {} crop{} of {}x{} pixels, {} spp{} (shots {}..{})", names,
               geometry.frameStart, geometry.frameEnd, geometry.windows.size(),
               geometry.windows.size() > 1 ? "s" : "", geometry.width, geometry.height, candidates.front().spp(),
               round == ProbeRound::AtShotSpp ? ", again at the shot's own spp" : "", ids.front().front(),
               ids.back().back());
  return ids;
}

// What the probe shots `ids` of `candidate` (one per crop) cost and erred at the shot's
// spp, once they end; they rendered probeSppRatio(candidate, round) times its spp.
// pt's probe comes first: its frames become `truthStandIn`, which the others are measured
// against.
CandidateMeasure measureProbe(FarmClient& client, const std::vector<int64_t>& ids, const ShotSpec& candidate,
                              const ProbeGeometry& geometry, const std::filesystem::path& probeFolder,
                              ProbeRound round, const std::function<void(const ShotSummary&)>& progress,
                              std::map<std::string, FrameImage>& truthStandIn) {
  const Pipeline pipeline = candidate.pipeline();
  const double sppScale = probeSppRatio(candidate, round);
  const std::string name(pipelineName(pipeline));
  CandidateMeasure measure;
  measure.pipeline = pipeline;
  measure.sppRatio = sppScale;
  std::map<std::string, FrameImage> frames;
  for (size_t window = 0; window < ids.size(); ++window) {
    const int64_t id = ids[window];
    const ShotSummary summary = client.watch(id, progress);
    if (summary.state() != SHOT_DONE) {
      measure.failure = "shot " + std::to_string(id) + " " + ShotState_Name(summary.state()) +
                        (summary.failure().empty() ? "" : ": " + summary.failure());
      if (pipeline == PIPELINE_PT)
        throw std::runtime_error("pipeline auto: plain pt's probe, which the others are measured against, did not "
                                 "finish: " + measure.failure);
      spdlog::warn("pipeline auto: the {} probe did not finish ({}); it is left out", name, measure.failure);
      return measure;
    }
    fetchFrames(client, id, window, probeOutput(probeFolder, pipeline, geometry, window, round), frames);
    const ShotReport report = client.report(id);
    measure.probeCoreSeconds += report.core_seconds();
    // Plain pt's probe renders more samples than the shot, tgpt's fewer: at the shot's
    // spp their renders would cost that much less (more), and they would err that much
    // more (less). Their other stages cost the same at any spp.
    for (const StageCost& stage : report.stages())
      measure.coreSecondsPerFrame += stage.stage() == "render" ? stage.core_seconds() / sppScale : stage.core_seconds();
  }
  measure.coreSecondsPerFrame /= static_cast<double>(geometry.frameCountOf(candidate));
  if (pipeline == PIPELINE_PT) truthStandIn = frames;
  const MeanEstimate error = estimatedRelMse(frames, truthStandIn, pipeline == PIPELINE_PT);
  measure.relMse = error.mean() * sppScale;
  measure.relMseStandardError = error.standardError() * sppScale;
  spdlog::info("pipeline auto: {} probe at {} spp: {:.2f} core-seconds a frame, estimated relMSE {:.5f} ± {:.5f}",
               name, std::lround(candidate.spp() * sppScale), measure.coreSecondsPerFrame, measure.relMse,
               measure.relMseStandardError);
  return measure;
}

}  // namespace

ShotSpec choosePipeline(FarmClient& client, const ShotFile& file, const ShotSpec& autoSpec,
                        const std::filesystem::path& probeFolder,
                        const std::function<void(const ShotSummary&)>& progress, const std::string& submitKey) {
  const std::vector<ShotSpec> candidates = candidateSpecs(file, autoSpec);
  int longestInterval = 1;
  for (const ShotSpec& c : candidates) longestInterval = std::max(longestInterval, c.keyframe_interval());
  const ProbeGeometry geometry = probeGeometry(autoSpec, longestInterval);
  const std::vector<std::vector<int64_t>> ids =
      submitProbes(client, candidates, geometry, probeFolder, submitKey, ProbeRound::First);
  std::vector<CandidateMeasure> measures;
  std::map<std::string, FrameImage> truthStandIn;
  for (size_t i = 0; i < candidates.size(); ++i)
    measures.push_back(measureProbe(client, ids[i], candidates[i], geometry, probeFolder, ProbeRound::First, progress,
                                    truthStandIn));
  const auto candidateOf = [&](Pipeline pipeline) {
    return *std::find_if(candidates.begin(), candidates.end(), [&](const ShotSpec& c) { return c.pipeline() == pipeline; });
  };
  const auto probeAtShotSpp = [&](Pipeline pipeline) {
    const ShotSpec candidate = candidateOf(pipeline);
    const auto againIds = submitProbes(client, {candidate}, geometry, probeFolder, submitKey, ProbeRound::AtShotSpp);
    return measureProbe(client, againIds.front(), candidate, geometry, probeFolder, ProbeRound::AtShotSpp, progress,
                        truthStandIn);
  };

  PipelineChoice choice;
  try {
    choice = choosePipelineFromProbes(measures, geometry, autoSpec, probeAtShotSpp);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(std::string("pipeline auto: ") + e.what());
  }
  spdlog::info("{}", choice.reason);
  ShotSpec spec = candidateOf(choice.pipeline);
  spec.set_pipeline_reason(choice.reason + (spec.pipeline_reason().empty() ? "" : "; " + spec.pipeline_reason()));
  spec.set_predicted_core_seconds_per_frame(choice.predictedCoreSecondsPerFrame);
  spec.set_predicted_relmse(choice.predictedRelMse);
  spec.set_probe_core_seconds(choice.probeCoreSeconds);
  return withReferenceChosen(spec, *file.scene());
}

}  // namespace pathfarm::farm
