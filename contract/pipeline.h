#pragma once
// The pipelines a shot can run, in one place for every side of the farm: the client reads
// them from shot files and probes among them, the scheduler plans them, the worker runs
// their stages. The wire carries a Pipeline (pathfarm/shot.proto); this module says what
// each one is: its name, its family, its filtering stages, its keyframes and the shot-file
// keys that belong to it. Adding a pipeline touches this module, the planner and the
// worker's stage code.
#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pathfarm/shot.pb.h"

namespace pathfarm::farm {

enum class PipelineFamily {
  Choice,      // auto: the client's probe chooses one of the others before submitting
  Plain,       // pt: tiles of plain path tracing
  Filtering,   // d, du, di, dui: Zimmer et al. 2015
  Gradient,    // tgpt: Manzi et al. 2016
  Metropolis,  // pssmlt, mlt, tmlt: Van de Woestijne et al. 2017 and its baselines
  Noop,        // tasks that do nothing, for measuring the farm itself
};

// What a filtering pipeline does besides rendering keyframes.
struct FilteringStages {
  bool upsample = false;     // keyframes at 1/4 of the samples, filtered at half resolution
  bool interpolate = false;  // only every k-th frame is a keyframe
};

struct PipelineTraits {
  Pipeline pipeline;
  std::string_view name;  // as shot files, reports and frames' attributes spell it
  PipelineFamily family;
  std::string_view integrator;            // what renders its frames (renderer/setup/integrator_factory.h)
  FilteringStages stages;                 // Filtering only
  std::vector<std::string_view> keys;     // shot-file keys only this family reads
};

// Every pipeline, in the order messages list them.
const std::vector<PipelineTraits>& allPipelines();
// Throws std::invalid_argument for PIPELINE_UNSPECIFIED or a value no traits describe.
const PipelineTraits& traitsOf(Pipeline pipeline);
std::string_view pipelineName(Pipeline pipeline);
// The name, or "unknown pipeline N" for a value no traits describe (a stored spec from an
// older scheduler, a newer client's value): for messages and reports, never throws.
std::string pipelineLabel(Pipeline pipeline);
// The pipeline a name spells, or nothing.
std::optional<Pipeline> pipelineNamed(std::string_view name);
// "auto, pt, d, ...": every name, for messages.
std::string pipelineNames();

// False for a value no traits describe.
bool isFilteringPipeline(Pipeline pipeline);
bool isMetropolisPipeline(Pipeline pipeline);
// Throws std::invalid_argument for a pipeline that is not a filtering one.
FilteringStages stagesOf(Pipeline pipeline);
// The rendered frames of a filtering shot: every frame, or with interpolation every k-th
// from the first, and the last.
std::vector<int64_t> keyframesOf(const ShotSpec& spec);
// The most baseline renders of one evaluation frame (ShotSpec.baseline_repeats): the
// evaluate task holds them all (a 1080p render is about 50 MB).
inline constexpr int kMaxBaselineRepeats = 16;
// How many baseline renders an evaluation frame gets (ShotSpec.baseline_repeats; 0 is 1).
inline int baselineRepeatsOf(const ShotSpec& spec) { return spec.baseline_repeats() > 1 ? spec.baseline_repeats() : 1; }

// Rows per window of a filter task that runs in windows (ShotSpec.filter_window_rows, 0),
// and the fewest a shot may ask for (a tile near a window reaches every window within
// kCompositeHalo of it).
inline constexpr int kDefaultFilterWindowRows = 512;
inline constexpr int kMinFilterWindowRows = 16;
// How far beyond its window a composite window reads the re-render tiles: every pixel its
// denoise compares and every firefly whose spread reaches the window
// (worker/composite_task.cpp checks that its filters reach no farther).
inline constexpr int kCompositeHalo = 32;
// The samples of reflectance an in-between frame's feature render takes (task parameter
// reflectance_spp), whose reflectance the interpolate task then uses at texture edges: the
// keyframes' spp, but no more than kMaxOwnReflectanceSpp. A reflectance sample costs
// about half a path's on the suite, and past 16 samples a pixel's reflectance at an edge is
// no longer what limits the interpolation (docs/performance.md, "Reflectance samples for
// the in-between frames").
inline constexpr int kMaxOwnReflectanceSpp = 16;
inline int ownReflectanceSpp(int keyframeSpp) { return std::min(keyframeSpp, kMaxOwnReflectanceSpp); }
// The samples per pixel of a filtering shot's keyframe renders: a quarter of spp with `u`
// (they are denoised at half resolution and upsampled), else spp.
int keyframeSppOf(const ShotSpec& spec);
// The samples per pixel of a filtering shot's sparse re-render: ShotSpec.rerender_spp when
// given, at most spp; spp by default. Half of spp beside a dui shot's quarter-spp keyframes
// cost less at equal error on the dolly and the courtyard at 256 spp, but more on the
// showroom (its caustic under the glass ball is re-rendered) and on the dolly at 64 spp
// (docs/performance.md, "The sparse re-render at half the samples").
int rerenderSppOf(const ShotSpec& spec);
// Rows first .. end - 1 of a frame.
struct RowWindow {
  int first = 0, end = 0;
};
// The windows a frame of the shot is filtered in, top to bottom: as few as hold at most
// filter_window_rows rows each (one more where a border moves up to an even row, so that
// a half-resolution denoise has whole rows), of heights that differ by at most two rows.
std::vector<RowWindow> filterWindowsOf(const ShotSpec& spec);

}  // namespace pathfarm::farm
