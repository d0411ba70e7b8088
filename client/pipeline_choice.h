#pragma once
// `pipeline: "auto"` (docs/pipeline-choice.md): which pipeline a shot runs, decided from a
// probe. Every candidate renders the same few frames of the shot, cropped to the centre
// of the picture at the shot's pixel size (filters judged on a downscaled frame see
// textures and edges finer than the shot's and err differently), as a shot of its own.
// An independent plain pt render of those frames (its samples start at
// kIndependentFirstSample) stands in for the truth. Each candidate's error is its relMSE
// against that render less the render's own noise, and pt's error is that noise. The
// winner is the candidate with the lowest cost at equal error against pt: its probe
// core-seconds over pt's, times its error over pt's (pt's error falls as 1/spp). This file
// holds the arithmetic; pipeline_probe.h runs the probe on a farm.
#include <filesystem>
#include <string>
#include <vector>

#include "contract/pipeline.h"
#include "pathfarm/shot.pb.h"

namespace pathfarm::farm {

// The pipelines auto chooses among, plain pt first. The Metropolis pipelines are not
// probed: their chains need the shot's whole window to be measured fairly.
const std::vector<Pipeline>& autoCandidates();

// The frames and the centre crop every probe renders.
struct ProbeGeometry {
  int64_t frameStart = 0, frameEnd = 0;  // inclusive
  int width = 0, height = 0;             // even, so upsampling pipelines can run
  int scale = 1;                         // about the shot's size over the crop's, per axis
  double zoom = 1;                       // exactly the shot's height over the crop's
  int64_t frames() const { return frameEnd - frameStart + 1; }
};

// Frames: enough for every candidate's keyframe interval (longestInterval + 1) and at
// least 5, from the middle of the shot. Crop: per axis 1/scale of the shot's, scale the
// least (1 to 4) that keeps the probe's estimated cost near 5 % of a plain pt shot, and
// no edge under 32 pixels unless the shot's is.
ProbeGeometry probeGeometry(const ShotSpec& shot, int longestInterval);

// Plain pt's probe renders this many times the shot's spp: it stands in for the truth, and
// its noise sets how small an error the probe can resolve (on the courtyard, where the sun
// makes fireflies, at the shot's spp it could not tell d or tgpt from zero, and auto chose
// pt, the worst of the three). Its cost and error at the shot's spp follow from 1/spp.
inline constexpr int kStandInSppFactor = 4;

// A candidate's probe: its spec over the probe's frames and crop, without measurements,
// writing into folder/<pipeline>. pt's samples start at kIndependentFirstSample, so that
// it can stand in for the truth: it shares no sample with the other candidates.
ShotSpec probeSpecOf(const ShotSpec& candidate, const ProbeGeometry& geometry, const std::filesystem::path& folder);

// What the probe measured of one candidate.
struct CandidateMeasure {
  Pipeline pipeline = PIPELINE_UNSPECIFIED;
  double coreSeconds = 0;       // the probe shot's at the shot's spp
  double probeCoreSeconds = 0;  // what the probe shot cost (plain pt's renders more samples)
  double relMse = 0;       // against the truth, estimated; pt's: the stand-in's own noise
  double relMseStandardError = 0;  // of that estimate
  std::string failure;     // non-empty: the probe shot failed, and this is why
};

struct PipelineChoice {
  Pipeline pipeline = PIPELINE_UNSPECIFIED;
  std::string reason;  // the table of predictions behind it, for the report
  double predictedCoreSecondsPerFrame = 0;
  double predictedRelMse = 0;
  double probeCoreSeconds = 0;  // every probe shot's, the stand-in's too
};

// The measures include pt: the stand-in's cost and noise. Throws std::invalid_argument
// without it, or when it failed.
PipelineChoice decidePipeline(const std::vector<CandidateMeasure>& measures, const ProbeGeometry& geometry,
                              const ShotSpec& shot);

}  // namespace pathfarm::farm
