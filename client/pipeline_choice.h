#pragma once
// `pipeline: "auto"` (docs/pipeline-choice.md): which pipeline a shot runs, decided from a
// probe. Every candidate renders the same few frames of the shot, cropped to the centre
// of the picture or to a grid of crops over it, at the shot's pixel size (filters judged on
// a downscaled frame see textures and edges finer than the shot's and err differently),
// each crop as a shot of its own.
// An independent plain pt render of those frames (its samples start at
// kIndependentFirstSample) stands in for the truth. Each candidate's error is its relMSE
// against that render less the render's own noise, and pt's error is that noise. The
// winner is the candidate with the lowest cost at equal error against pt: its probe
// core-seconds over pt's, times its error over pt's (pt's error falls as 1/spp). This file
// holds the arithmetic; pipeline_probe.h runs the probe on a farm.
#include <filesystem>
#include <functional>
#include <utility>
#include <string>
#include <vector>

#include "contract/pipeline.h"
#include "pathfarm/shot.pb.h"

namespace pathfarm::farm {

// The pipelines auto chooses among, plain pt first. The Metropolis pipelines are not
// probed: their chains need the shot's whole window to be measured fairly.
const std::vector<Pipeline>& autoCandidates();

// Where a probe's crop lies: its centre's offset from the picture's centre, in fractions
// of the picture's width (right) and height (down) (ShotSpec.camera_shift_x and _y).
struct ProbeWindow {
  double shiftX = 0, shiftY = 0;
};

// The frames and the crops every probe renders.
struct ProbeGeometry {
  int64_t frameStart = 0, frameEnd = 0;  // inclusive
  // The frames errors are measured on (inclusive), which plain pt's stand-in alone renders:
  // the probe's inner frames where the shot goes on past both of its ends. A shot's frames
  // have neighbours on both sides, and a probe's first and last frames do not: d denoises
  // them from one neighbour and tgpt's Poisson window ends there.
  int64_t measuredStart = 0, measuredEnd = 0;
  int width = 0, height = 0;             // of each crop; even, so upsampling pipelines can run
  int scale = 1;                         // about the shot's size over a crop's, per axis
  double zoom = 1;                       // exactly the shot's height over a crop's
  std::vector<ProbeWindow> windows{ProbeWindow{}};  // one crop each
  int64_t frames() const { return frameEnd - frameStart + 1; }
  int64_t measuredFrames() const { return measuredEnd - measuredStart + 1; }
  // The frames `candidate` renders (inclusive): an interpolating one (keyframe_interval >
  // 1) all of them; plain pt's stand-in the measured ones; the others those and a
  // neighbour on each side, which is all a measured frame of theirs reads.
  std::pair<int64_t, int64_t> framesOf(const ShotSpec& candidate) const;
  int64_t frameCountOf(const ShotSpec& candidate) const {
    const auto [first, last] = framesOf(candidate);
    return last - first + 1;
  }
  // Every crop's pixels together.
  double pixels() const { return static_cast<double>(width) * height * static_cast<double>(windows.size()); }
};

// Frames: enough for every candidate's keyframe interval (longestInterval + 1) and at
// least 5 (from 256 spp, 4), from the middle of the shot; errors are measured on the middle
// 3 (from 256 spp, 2) where the probe has frames on both sides of them. Crops: about
// 1/scale² of the shot's pixels, scale the least (1 to 4) that keeps the probe's estimated
// cost near 5 % of a plain pt shot.
// Where the shot is large enough, a grid of 3 x 3 crops of 1/(3 scale) per axis, centred
// on the ninths of the picture, at least 32 rows each (as long as that keeps them within
// 1.5 times one crop's pixels): a shot's centre is often its hardest part, and on the
// dolly at 640x360 the centre alone read d's error at 0.48 of pt's where the whole frame
// has 0.19 (the grid: 0.18). Otherwise one crop at the centre, no edge under 32 pixels
// unless the shot's is.
ProbeGeometry probeGeometry(const ShotSpec& shot, int longestInterval);

// Plain pt's probe stands in for the truth, and its noise sets how small an error the probe
// can resolve: it renders twice the shot's spp, and at low spp up to 4 times as far as
// kStandInFloorSpp. On the courtyard, where the sun makes fireflies, at the shot's 64 spp it
// could not tell d or tgpt from zero, and auto chose pt, the worst of the three; at twice
// the spp d's estimate still erred ±0.08 against pt's 0.30, at 4 times ±0.03. At 256 spp
// on the dolly and the courtyard (640x360), 2 times read every candidate's error within a
// standard error of 4 times' and chose alike, for 0.72 to 0.75 of the probe's cost
// (docs/performance.md). Its cost and error at the shot's spp follow from 1/spp.
inline constexpr int kStandInSppFactor = 2;
inline constexpr int kStandInMaxSppFactor = 4;
inline constexpr int kStandInFloorSpp = 256;
int standInSpp(int shotSpp);
// tgpt's first probe renders a kGradientProbeSppDivisor-th of the shot's spp where that
// leaves at least kGradientProbeMinSpp: it is the costliest candidate by far (5 to 6 times
// plain pt's per sample). Its error and its render's cost at the shot's spp are taken to
// follow 1/spp as pt's do (the screened Poisson reconstruction is nearly linear in its
// noisy inputs; the reconstruction's own cost does not change). That holds roughly on the
// dolly's centre at 640x360 (frame 11, against 16384 spp: tgpt at 64 spp erred 3.2 times
// what it did at 256, so the quarter reads its error about 20 % low), and not on the
// creature, whose rare caustic paths a quarter of the samples mostly misses: there the
// quarter read tgpt's error 4.75 times lower than a probe at the shot's spp, and auto chose
// tgpt where d cost a quarter as much. So a winner probed at fewer samples is probed again
// at the shot's spp before it is chosen (ProbeRound::AtShotSpp, choosePipelineFromProbes):
// a quarter-spp reading that loses was already the optimistic one. Below the floor a
// render task's fixed costs would weigh too much in its cost to scale it.
inline constexpr int kGradientProbeSppDivisor = 4;
inline constexpr int kGradientProbeMinSpp = 16;

// A candidate's probes: the first, which every candidate has, and a second at the shot's
// own spp for a first-round winner whose first probe rendered fewer samples.
enum class ProbeRound { First, AtShotSpp };

// The probe's spp over the shot's for a candidate: what its probe's render cost is divided
// by and its error multiplied by to give them at the shot's spp.
double probeSppRatio(const ShotSpec& candidate, ProbeRound round = ProbeRound::First);

// A candidate's probe of one crop (an index into geometry.windows): its spec over the
// probe's frames and that crop, without measurements, writing into folder/<pipeline>
// (folder/<pipeline>/window_<i> with several crops). pt's samples start at
// kIndependentFirstSample, so that it can stand in for the truth: it shares no sample with
// the other candidates.
// The second round's probe is named and kept apart from the first's (folder/<pipeline>_at_shot_spp).
ShotSpec probeSpecOf(const ShotSpec& candidate, const ProbeGeometry& geometry, size_t window,
                     const std::filesystem::path& folder, ProbeRound round = ProbeRound::First);
// Where that probe writes its frames.
std::filesystem::path probeOutput(const std::filesystem::path& folder, Pipeline pipeline,
                                  const ProbeGeometry& geometry, size_t window, ProbeRound round = ProbeRound::First);

// What the probe measured of one candidate.
struct CandidateMeasure {
  Pipeline pipeline = PIPELINE_UNSPECIFIED;
  double coreSecondsPerFrame = 0;  // the probe shot's at the shot's spp, per frame it rendered
  double probeCoreSeconds = 0;  // what the probe shot cost (plain pt's renders more samples)
  double relMse = 0;       // against the truth, estimated; pt's: the stand-in's own noise
  double relMseStandardError = 0;  // of that estimate
  double sppRatio = 1;     // the probe's spp over the shot's (probeSppRatio)
  std::string failure;     // non-empty: the probe shot failed, and this is why
};

struct PipelineChoice {
  Pipeline pipeline = PIPELINE_UNSPECIFIED;
  std::string reason;  // the table of predictions behind it, for the report
  double predictedCoreSecondsPerFrame = 0;
  double predictedRelMse = 0;
  double costAtEqualError = 0;  // predicted, against plain pt's
  double probeCoreSeconds = 0;  // every probe shot's, the stand-in's too
};

// The measures include pt: the stand-in's cost and noise. Throws std::invalid_argument
// without it, or when it failed.
PipelineChoice decidePipeline(const std::vector<CandidateMeasure>& measures, const ProbeGeometry& geometry,
                              const ShotSpec& shot);

// decidePipeline, except that a winner whose probe rendered fewer samples than the shot
// is measured again by `probeAtShotSpp` (its probe at ProbeRound::AtShotSpp) and the
// choice made again with that measure in place of the first; the reason says so, and the
// probe's cost counts both.
PipelineChoice choosePipelineFromProbes(std::vector<CandidateMeasure> measures, const ProbeGeometry& geometry,
                                        const ShotSpec& shot,
                                        const std::function<CandidateMeasure(Pipeline)>& probeAtShotSpp);

}  // namespace pathfarm::farm
