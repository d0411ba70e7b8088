#include "client/pipeline_choice.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "renderer/integrators/frame_renderer.h"

namespace pathfarm::farm {
namespace {

// Probe frames, and the middle ones measured. Below kFewerFramesFromSpp a frame's
// estimates are noisier: with 2 measured frames at 64 spp the courtyard's d read within the
// probe's noise, and auto chose tgpt at 5 times d's cost at equal error; with 3 it chose d.
// At 256 spp 2 frames read every estimate within a standard error of 3
// (docs/performance.md). A longer interval lengthens the probe, not what is measured.
constexpr int64_t kMinProbeFrames = 5;
constexpr int64_t kMinProbeFramesAtHighSpp = 4;
constexpr int64_t kMeasuredFrames = 3;
constexpr int64_t kMeasuredFramesAtHighSpp = 2;
constexpr int kFewerFramesFromSpp = 256;
constexpr int kMaxProbeScale = 4;
constexpr int kMinProbeEdge = 32;
// The probe's cost, in plain pt frames of its size per probe frame: d 1.1, di 0.6, dui 0.4,
// tgpt about 5.5 at a kGradientProbeSppDivisor-th of the spp (docs/performance.md); plain
// pt's, at standInSpp, on the measured frames only, comes on top.
constexpr double kInterpolatingCostInPtFrames = 0.6 + 0.4;
constexpr double kOthersCostInPtFrames = 1.1 + 5.5 / kGradientProbeSppDivisor;
constexpr double kProbeBudget = 0.05;  // of a plain pt shot
// Crops per axis of a probe spread over the picture; their floor of kMinProbeEdge rows may
// take their pixels this far past one crop's.
constexpr int kProbeGrid = 3;
constexpr double kGridOverBudget = 1.5;
// An estimate within this many standard errors of zero is within the probe's noise: it
// counts as that bound, so that noise cannot pick a winner. Below kNegligibleError no
// error counts apart.
constexpr double kResolvableStandardErrors = 2;
constexpr double kNegligibleError = 1e-8;

std::string printed(const char* pattern, double value) {
  char text[64];
  std::snprintf(text, sizeof text, pattern, value);
  return text;
}

// What a second-round probe's name and folder carry after the pipeline's name.
std::string roundSuffix(ProbeRound round, const char* separator) {
  return round == ProbeRound::AtShotSpp ? separator + std::string("at_shot_spp") : "";
}

int evenUp(int edge) { return edge + edge % 2; }

int probeEdge(int shotEdge, int scale) {
  const int edge = shotEdge / scale;
  return std::min(shotEdge + shotEdge % 2, edge + edge % 2);
}

}  // namespace

const std::vector<Pipeline>& autoCandidates() {
  static const std::vector<Pipeline> candidates = {PIPELINE_PT, PIPELINE_D, PIPELINE_DI, PIPELINE_DUI, PIPELINE_TGPT};
  return candidates;
}

ProbeGeometry probeGeometry(const ShotSpec& shot, int longestInterval) {
  const int64_t shotFrames = shot.frame_end() - shot.frame_start() + 1;
  const int64_t fewest = shot.spp() >= kFewerFramesFromSpp ? kMinProbeFramesAtHighSpp : kMinProbeFrames;
  const int64_t frames = std::min(shotFrames, std::max<int64_t>(fewest, longestInterval + 1));
  ProbeGeometry geometry;
  geometry.frameStart = shot.frame_start() + (shotFrames - frames) / 2;
  geometry.frameEnd = geometry.frameStart + frames - 1;
  const bool innerFramesOnly = frames >= kMinProbeFramesAtHighSpp && geometry.frameStart > shot.frame_start() &&
                               geometry.frameEnd < shot.frame_end();
  const int64_t measured = shot.spp() >= kFewerFramesFromSpp ? kMeasuredFramesAtHighSpp : kMeasuredFrames;
  geometry.measuredStart = innerFramesOnly ? geometry.frameStart + (frames - measured) / 2 : geometry.frameStart;
  geometry.measuredEnd = innerFramesOnly ? geometry.measuredStart + measured - 1 : geometry.frameEnd;
  // The probe costs this many plain pt frames of the shot's size, over scale^2.
  const double standInFactor = static_cast<double>(standInSpp(shot.spp())) / shot.spp();
  const double neighbouredFrames = static_cast<double>(std::min(frames, geometry.measuredFrames() + 2));
  const double cost = kInterpolatingCostInPtFrames * static_cast<double>(frames) +
                      kOthersCostInPtFrames * neighbouredFrames +
                      standInFactor * static_cast<double>(geometry.measuredFrames());
  const double scale = std::sqrt(cost / (kProbeBudget * static_cast<double>(shotFrames)));
  const int largestScale = std::max(1, std::min(shot.width(), shot.height()) / kMinProbeEdge);
  geometry.scale = std::clamp(static_cast<int>(std::ceil(scale)), 1, std::min(kMaxProbeScale, largestScale));
  // A grid of crops, together about the pixels of one crop of 1/scale per axis, where
  // crops of at least kMinProbeEdge rows keep it within kGridOverBudget of that.
  const int gridHeight = evenUp(std::max(kMinProbeEdge, shot.height() / (kProbeGrid * geometry.scale)));
  const int gridWidth = evenUp(static_cast<int>(std::lround(gridHeight * static_cast<double>(shot.width()) /
                                                            shot.height())));
  const double onePixels = static_cast<double>(shot.width()) * shot.height() / (geometry.scale * geometry.scale);
  const bool grid = geometry.scale > 1 && kProbeGrid * gridWidth <= shot.width() &&
                    kProbeGrid * gridHeight <= shot.height() &&
                    kProbeGrid * kProbeGrid * static_cast<double>(gridWidth) * gridHeight <= kGridOverBudget * onePixels;
  geometry.width = grid ? gridWidth : probeEdge(shot.width(), geometry.scale);
  geometry.height = grid ? gridHeight : probeEdge(shot.height(), geometry.scale);
  geometry.zoom = static_cast<double>(shot.height()) / geometry.height;
  if (grid) {
    geometry.windows.clear();
    for (int row = 0; row < kProbeGrid; ++row)
      for (int column = 0; column < kProbeGrid; ++column)
        geometry.windows.push_back({(column + 0.5) / kProbeGrid - 0.5, (row + 0.5) / kProbeGrid - 0.5});
  }
  return geometry;
}

int standInSpp(int shotSpp) {
  return std::max(kStandInSppFactor * shotSpp, std::min(kStandInMaxSppFactor * shotSpp, kStandInFloorSpp));
}

std::pair<int64_t, int64_t> ProbeGeometry::framesOf(const ShotSpec& candidate) const {
  if (candidate.pipeline() == PIPELINE_PT) return {measuredStart, measuredEnd};
  if (candidate.keyframe_interval() > 1) return {frameStart, frameEnd};
  return {std::max(frameStart, measuredStart - 1), std::min(frameEnd, measuredEnd + 1)};
}

double probeSppRatio(const ShotSpec& candidate, ProbeRound round) {
  if (round == ProbeRound::AtShotSpp) return 1;
  if (candidate.pipeline() == PIPELINE_PT) return static_cast<double>(standInSpp(candidate.spp())) / candidate.spp();
  if (candidate.pipeline() == PIPELINE_TGPT && candidate.spp() / kGradientProbeSppDivisor >= kGradientProbeMinSpp)
    return static_cast<double>(candidate.spp() / kGradientProbeSppDivisor) / candidate.spp();
  return 1;
}

std::filesystem::path probeOutput(const std::filesystem::path& folder, Pipeline pipeline,
                                  const ProbeGeometry& geometry, size_t window, ProbeRound round) {
  const std::filesystem::path own = folder / (std::string(pipelineName(pipeline)) + roundSuffix(round, "_"));
  return geometry.windows.size() > 1 ? own / ("window_" + std::to_string(window)) : own;
}

ShotSpec probeSpecOf(const ShotSpec& candidate, const ProbeGeometry& geometry, size_t window,
                     const std::filesystem::path& folder, ProbeRound round) {
  ShotSpec probe = candidate;
  const std::string name(pipelineName(candidate.pipeline()));
  const std::string windowName = geometry.windows.size() > 1 ? ".window_" + std::to_string(window) : "";
  probe.set_name(candidate.name() + ".probe." + name + roundSuffix(round, ".") + windowName);
  const auto [first, last] = geometry.framesOf(candidate);
  probe.set_frame_start(first);
  probe.set_frame_end(last);
  probe.set_width(geometry.width);
  probe.set_height(geometry.height);
  probe.set_output(probeOutput(folder, candidate.pipeline(), geometry, window, round).string());
  probe.set_reference_spp(0);
  probe.clear_evaluation_frames();
  probe.clear_baseline_core_seconds();
  if (candidate.pipeline() == PIPELINE_TGPT) {
    probe.set_poisson_window(static_cast<int>(std::min<int64_t>(candidate.poisson_window(), last - first + 1)));
    probe.set_poisson_overlap(std::min(candidate.poisson_overlap(), probe.poisson_window() - 1));
  }
  if (geometry.zoom > 1) probe.set_camera_zoom(geometry.zoom);
  probe.set_camera_shift_x(geometry.windows.at(window).shiftX);
  probe.set_camera_shift_y(geometry.windows.at(window).shiftY);
  if (candidate.pipeline() == PIPELINE_PT) {
    probe.set_first_sample(kIndependentFirstSample);
  }
  probe.set_spp(static_cast<int>(std::lround(candidate.spp() * probeSppRatio(candidate, round))));
  return probe;
}

PipelineChoice decidePipeline(const std::vector<CandidateMeasure>& measures, const ProbeGeometry& geometry,
                              const ShotSpec& shot) {
  const auto pt = std::find_if(measures.begin(), measures.end(), [](const auto& m) { return m.pipeline == PIPELINE_PT; });
  if (pt == measures.end() || !pt->failure.empty() || !(pt->coreSecondsPerFrame > 0))
    throw std::invalid_argument("the probe needs plain pt's render to measure the others against" +
                                (pt == measures.end() || pt->failure.empty() ? std::string() : ": " + pt->failure));
  PipelineChoice choice;
  const double pixelRatio = static_cast<double>(shot.width()) * shot.height() / geometry.pixels();
  const double ptError = std::max(pt->relMse, kNegligibleError);
  double best = 0;
  std::string table;
  for (const CandidateMeasure& m : measures) {
    choice.probeCoreSeconds += m.probeCoreSeconds;
    if (!table.empty()) table += ", ";
    const std::string name(pipelineName(m.pipeline));
    if (!m.failure.empty()) {
      table += name + " failed (" + m.failure + ")";
      continue;
    }
    const double floor = std::max(kResolvableStandardErrors * m.relMseStandardError, kNegligibleError);
    const double error = std::max(m.relMse, floor);
    const double cost = m.coreSecondsPerFrame / pt->coreSecondsPerFrame * error / ptError;
    table += name + " " + printed("%.2f", cost) + (m.relMse < floor ? " (its error within the probe's noise)" : "");
    if (choice.pipeline != PIPELINE_UNSPECIFIED && cost >= best) continue;
    best = cost;
    choice.costAtEqualError = cost;
    choice.pipeline = m.pipeline;
    choice.predictedRelMse = error;
    choice.predictedCoreSecondsPerFrame = m.coreSecondsPerFrame * pixelRatio;
  }
  const std::string crops = geometry.windows.size() > 1
                                ? std::to_string(geometry.windows.size()) + " crops of " + std::to_string(geometry.width) +
                                      "x" + std::to_string(geometry.height) + " pixels spread over the picture"
                                : "the centre " + std::to_string(geometry.width) + "x" + std::to_string(geometry.height) +
                                      " pixels";
  const std::string probe = "probe: frames " + std::to_string(geometry.frameStart) + ".." +
                            std::to_string(geometry.frameEnd) + ", " + crops + ", " + std::to_string(shot.spp()) +
                            " spp, " + printed("%.1f", choice.probeCoreSeconds) + " core-seconds";
  choice.reason = "auto chose " + std::string(pipelineName(choice.pipeline)) + ", the lowest predicted cost at equal error against plain pt: " +
                  table + " (" + probe + ")";
  return choice;
}

PipelineChoice choosePipelineFromProbes(std::vector<CandidateMeasure> measures, const ProbeGeometry& geometry,
                                        const ShotSpec& shot,
                                        const std::function<CandidateMeasure(Pipeline)>& probeAtShotSpp) {
  PipelineChoice choice = decidePipeline(measures, geometry, shot);
  std::string firstRounds;
  const auto winnerOf = [&] {
    return std::find_if(measures.begin(), measures.end(),
                        [&](const CandidateMeasure& m) { return m.pipeline == choice.pipeline; });
  };
  // Each pass measures one more candidate at the shot's spp, so there are at most as many
  // passes as candidates.
  for (auto winner = winnerOf(); winner->sppRatio < 1; winner = winnerOf()) {
    const std::string name(pipelineName(winner->pipeline));
    firstRounds += "; " + name + " won at " + printed("%.0f", winner->sppRatio * shot.spp()) + " spp (" +
                   printed("%.2f", choice.costAtEqualError) + ") and was probed again at the shot's " +
                   std::to_string(shot.spp());
    CandidateMeasure again = probeAtShotSpp(winner->pipeline);
    if (again.sppRatio < 1) throw std::logic_error("a probe again at the shot's spp rendered fewer samples");
    again.probeCoreSeconds += winner->probeCoreSeconds;
    *winner = std::move(again);
    choice = decidePipeline(measures, geometry, shot);
  }
  choice.reason += firstRounds;
  return choice;
}

}  // namespace pathfarm::farm
