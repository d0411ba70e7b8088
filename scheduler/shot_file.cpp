#include "scheduler/shot_file.h"

#include <fstream>
#include <sstream>

#include "renderer/decomposition/auto_decomposition.h"
#include "renderer/metropolis/metropolis_renderer.h"
#include "scheduler/keyframe_probe.h"
#include "scheduler/planner.h"
#include "renderer/scene/json_node.h"
#include "renderer/scene/scene_loader.h"

namespace pathfarm::farm {
namespace {

constexpr double kDefaultRerenderBound = 0.25;

// The frames measured for the report: two neighbours in the middle of the shot (the first
// an in-between frame when keyframes are k > 1 apart), so that the temporal error has a pair.
std::vector<int64_t> defaultEvaluationFrames(const ShotSpec& spec) {
  const int64_t middle = spec.frame_start() + (spec.frame_end() - spec.frame_start()) / 2;
  const int64_t first = middle == spec.frame_start() && middle < spec.frame_end() ? middle + 1 : middle;
  std::vector<int64_t> frames = {first};
  if (first + 1 <= spec.frame_end()) frames.push_back(first + 1);
  return frames;
}

// `probeKeyframes` false only checks the keys: "keyframe_interval": "auto" stays unresolved.
void readFilteringKeys(const JsonNode& root, const Scene& scene, ShotSpec& spec, bool probeKeyframes = true) {
  spec.set_feature_spp(root.has("feature_spp") ? root["feature_spp"].integer(1, 1 << 20) : 4);
  if (!stagesOf(spec.pipeline()).interpolate) {
    spec.set_keyframe_interval(1);
    spec.set_keyframe_reason("k = 1: the pipeline does not interpolate");
    return;
  }
  const double bound = root.has("rerender_bound") ? root["rerender_bound"].number(0.0, 1.0) : kDefaultRerenderBound;
  const auto interval = root.optional("keyframe_interval");
  if (interval && !(interval->isString() && interval->string() == "auto")) {
    spec.set_keyframe_interval(interval->integer(1, 1000));
    spec.set_keyframe_reason("k = " + std::to_string(spec.keyframe_interval()) + ": given in the shot file");
    return;
  }
  if (!probeKeyframes) return;
  const KeyframeChoice choice = chooseKeyframeInterval(scene, spec, bound);
  spec.set_keyframe_interval(choice.interval);
  spec.set_keyframe_reason(choice.reason);
  // dui with every frame a keyframe interpolates nothing and only upsamples quarter-sample
  // renders, which loses what no half-resolution filter restores (texture edges, thin
  // lines): on the moving-camera suite that cost 3x pt at equal error, d 0.9x
  // (docs/performance.md). So such a shot renders every frame at full spp and denoises it.
  if (choice.interval == 1 && spec.pipeline() == "dui") {
    spec.set_pipeline("d");
    spec.set_pipeline_reason("the shot asked for dui, but its probe chose k = 1, so nothing would be interpolated: every "
                             "frame is rendered at the shot's spp and denoised instead of upsampled from a quarter of "
                             "the samples");
  }
}

void readGradientKeys(const JsonNode& root, ShotSpec& spec) {
  spec.set_poisson_window(root.has("poisson_window") ? root["poisson_window"].integer(1, 1000) : 10);
  spec.set_poisson_overlap(root.has("poisson_overlap") ? root["poisson_overlap"].integer(0, spec.poisson_window() - 1) : 5);
  spec.set_poisson_norm(root.has("poisson_norm") ? root["poisson_norm"].string() : "l1");
  if (spec.poisson_norm() != "l1" && spec.poisson_norm() != "l2") root["poisson_norm"].fail("expected \"l1\" or \"l2\"");
}

// Defaults are the renderer's (MetropolisSettings), so a shot and `pathfarm render` agree.
void readMetropolisKeys(const JsonNode& root, const Scene& scene, ShotSpec& spec) {
  if (scene.camera.shutterClose <= scene.camera.shutterOpen)
    root["scene"].fail("the Metropolis pipelines need an open shutter; the scene's shutter has zero length");
  const MetropolisSettings defaults;
  spec.set_mlt_window(root.has("mlt_window") ? root["mlt_window"].integer(1, 1000) : 24);
  spec.set_mutations_per_pixel(root.has("mutations_per_pixel") ? root["mutations_per_pixel"].number(1e-6, 1e9)
                                                                 : spec.spp());
  spec.set_mlt_chains(root.has("mlt_chains") ? root["mlt_chains"].integer(1, 1 << 20) : defaults.chains);
  spec.set_chains_per_block(root.has("chains_per_block") ? root["chains_per_block"].integer(1, 1 << 20)
                                                         : defaults.chainsPerBlock);
  spec.set_chain_tasks(root.has("chain_tasks") ? root["chain_tasks"].integer(1, 1 << 20) : 8);
  spec.set_temporal_delta(root.has("temporal_delta") ? root["temporal_delta"].number(1e-6, 1e6) : defaults.temporalDelta);
  spec.set_tune_delta(root.has("tune_delta") && root["tune_delta"].boolean());
  spec.set_bootstrap_samples(root.has("bootstrap_samples") ? root["bootstrap_samples"].integer(1, 1 << 30)
                                                           : static_cast<int>(defaults.bootstrapSamples));
}

void readEvaluationKeys(const JsonNode& root, ShotSpec& spec) {
  spec.set_reference_spp(root.has("reference_spp") ? root["reference_spp"].integer(1, 1 << 24) : 0);
  if (root.has("baseline_core_seconds")) spec.set_baseline_core_seconds(root["baseline_core_seconds"].number(1e-9, 1e12));
  if (auto frames = root.optional("evaluation_frames")) {
    for (const JsonNode& frame : frames->elements()) {
      const int64_t value = frame.integer(0, 10'000'000);
      if (value < spec.frame_start() || value > spec.frame_end()) frame.fail("not a frame of the shot");
      spec.add_evaluation_frames(value);
    }
  } else if (spec.pipeline() != "pt" || spec.reference_spp() > 0) {
    for (const int64_t frame : defaultEvaluationFrames(spec)) spec.add_evaluation_frames(frame);
  }
}

// The keys of the spec's pipeline: its decomposition, resolved here once so that every
// worker splits the frames the same way (filtering pipelines split by default into what
// the scene can produce), and its filtering, gradient or Metropolis settings.
void readPipelineKeys(const JsonNode& root, const Scene& scene, ShotSpec& spec, bool probeKeyframes = true) {
  const bool filtering = isFilteringPipeline(spec.pipeline());
  const auto decompose = root.optional("decompose");
  const std::string decomposeText = decompose ? decompose->string() : filtering ? "auto" : "none";
  try {
    const auto decomposition = decompositionFor(scene, decomposeText);
    spec.set_decompose(decomposition ? decomposition->describe() : "none");
  } catch (const std::invalid_argument& e) {
    if (!decompose) root.fail(std::string("decompose: ") + e.what());
    decompose->fail(e.what());
  }
  if (filtering && spec.decompose() == "none") root["decompose"].fail("the filtering pipelines need a decomposition");
  if (filtering) readFilteringKeys(root, scene, spec, probeKeyframes);
  if (spec.pipeline() == "tgpt") readGradientKeys(root, spec);
  if (isMetropolisPipeline(spec.pipeline())) readMetropolisKeys(root, scene, spec);
}

}  // namespace

std::string readShotFileText(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw SceneError(file.string() + ": cannot open the shot file");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

ShotSpec loadShotFile(const std::filesystem::path& file) { return parseShotFile(readShotFileText(file), file); }

ShotSpec parseShotFile(std::string_view text, const std::filesystem::path& file, std::string_view pipeline) {
  const std::string label = file.string();
  const nlohmann::json document = parseJsonDocument(text, label);
  const JsonNode root(document, "", label);
  root.expectKeys({"name", "scene", "frames", "resolution", "spp", "max_depth", "pipeline", "tile", "output",
                   "priority", "max_attempts", "noop_tasks", "decompose", "keyframe_interval", "rerender_bound",
                   "feature_spp", "reference_spp", "evaluation_frames", "baseline_core_seconds",
                   "poisson_window", "poisson_overlap", "poisson_norm", "mlt_window", "mutations_per_pixel",
                   "mlt_chains", "chains_per_block", "chain_tasks", "temporal_delta", "tune_delta",
                   "bootstrap_samples", "required_tags", "max_workers"});
  const std::filesystem::path folder = std::filesystem::absolute(file).parent_path();

  ShotSpec spec;
  spec.set_name(root.has("name") ? root["name"].string() : file.stem().string());
  spec.set_pipeline(!pipeline.empty() ? std::string(pipeline) : root.has("pipeline") ? root["pipeline"].string() : "auto");
  const bool filtering = isFilteringPipeline(spec.pipeline());
  if (spec.pipeline() != "pt" && spec.pipeline() != "noop" && spec.pipeline() != "tgpt" && spec.pipeline() != "auto" &&
      !filtering && !isMetropolisPipeline(spec.pipeline()))
    root["pipeline"].fail("unknown pipeline \"" + spec.pipeline() +
                          "\" (this farm runs: auto, pt, d, du, di, dui, tgpt, pssmlt, mlt, tmlt, noop)");
  spec.set_priority(root.has("priority") ? root["priority"].integer(-1000, 1000) : 0);
  spec.set_max_attempts(root.has("max_attempts") ? root["max_attempts"].integer(1, 100) : 3);
  if (const auto tags = root.optional("required_tags")) {
    for (const JsonNode& tag : tags->elements()) {
      const std::string text = tag.string();
      if (!isValidTag(text)) tag.fail("a tag is letters, digits, '-', '_' or '.' (1 to 64 of them)");
      spec.add_required_tags(text);
    }
  }
  spec.set_max_workers(root.has("max_workers") ? root["max_workers"].integer(1, 1'000'000) : 0);
  spec.set_tile(root.has("tile") ? root["tile"].integer(8, 4096) : 64);
  spec.set_output((folder / (root.has("output") ? root["output"].string() : "output/" + spec.name()))
                      .lexically_normal()
                      .string());
  if (spec.pipeline() == "noop") {
    spec.set_noop_tasks(root["noop_tasks"].integer(1, 10'000'000));
    return spec;
  }

  const JsonNode sceneKey = root["scene"];
  const std::filesystem::path scenePath = (folder / sceneKey.string()).lexically_normal();
  const Scene scene = loadScene(scenePath);  // throws SceneError naming the scene file
  spec.set_scene(scenePath.string());
  spec.set_frame_start(scene.defaults.frameStart);
  spec.set_frame_end(scene.defaults.frameEnd);
  if (auto frames = root.optional("frames")) {
    frames->expectKeys({"start", "end"});
    spec.set_frame_start((*frames)["start"].integer(0, 10'000'000));
    spec.set_frame_end((*frames)["end"].integer(static_cast<int>(spec.frame_start()), 10'000'000));
  }
  spec.set_width(scene.defaults.width);
  spec.set_height(scene.defaults.height);
  if (auto resolution = root.optional("resolution")) {
    const auto e = resolution->elements();
    if (e.size() != 2) resolution->fail("expected [width, height]");
    spec.set_width(e[0].integer(1, 16384));
    spec.set_height(e[1].integer(1, 16384));
  }
  spec.set_spp(root.has("spp") ? root["spp"].integer(1, 1 << 20) : scene.defaults.spp);
  spec.set_max_depth(root.has("max_depth") ? root["max_depth"].integer(0, 1024) : scene.defaults.maxDepth);
  if (spec.pipeline() == "auto") {
    // The rest depends on the pipeline the probe chooses, which reads the file again as
    // each candidate. Their keys are checked now, so that a bad one is refused before any
    // probe runs; the keyframe probe waits for the candidates that interpolate.
    for (const char* candidate : {"dui", "tgpt"}) {
      ShotSpec checked = spec;
      checked.set_pipeline(candidate);
      readPipelineKeys(root, scene, checked, false);
    }
    readEvaluationKeys(root, spec);
    return spec;
  }
  readPipelineKeys(root, scene, spec);
  readEvaluationKeys(root, spec);
  // A shot the farm cannot plan is refused here, naming the reason. One too large for a
  // scheduler's default limits (a mistyped frame range or tile size could plan 10^13 tasks,
  // minutes and gigabytes of them) is not planned here: the scheduler it goes to refuses it
  // before planning, or plans it within its own limits.
  if (plannedTasksAtLeast(spec) <= ShotLimits{}.maxTasks) {
    try {
      planShot(spec);
    } catch (const PlanError& e) {
      root.fail(e.what());
    }
  }
  return spec;
}

}  // namespace pathfarm::farm
