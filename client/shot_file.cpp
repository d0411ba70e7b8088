#include "client/shot_file.h"

#include <algorithm>
#include <fstream>
#include <sstream>

#include "client/reference_choice.h"
#include "renderer/setup/auto_decomposition.h"
#include "renderer/metropolis/metropolis_renderer.h"
#include "renderer/scene/scene_loader.h"
#include "scheduler/planner.h"

namespace pathfarm::farm {
namespace {

constexpr double kDefaultRerenderBound = 0.25;

double readRerenderBound(const JsonNode& root) {
  return root.has("rerender_bound") ? root["rerender_bound"].number(0.0, 1.0) : kDefaultRerenderBound;
}

// The frames measured for the report: two neighbours in the middle of the shot (the first
// an in-between frame when keyframes are k > 1 apart), so that the temporal error has a pair.
std::vector<int64_t> defaultEvaluationFrames(const ShotSpec& spec) {
  const int64_t middle = spec.frame_start() + (spec.frame_end() - spec.frame_start()) / 2;
  const int64_t first = middle == spec.frame_start() && middle < spec.frame_end() ? middle + 1 : middle;
  std::vector<int64_t> frames = {first};
  if (first + 1 <= spec.frame_end()) frames.push_back(first + 1);
  return frames;
}

// A keyframe interval of "auto", or none given, stays 0: the keyframe probe chooses it
// (shot_preparation.h) within the file's rerender_bound.
void readFilteringKeys(const JsonNode& root, ShotSpec& spec) {
  spec.set_feature_spp(root.has("feature_spp") ? root["feature_spp"].integer(1, 1 << 20) : 4);
  if (root.has("rerender_spp")) spec.set_rerender_spp(root["rerender_spp"].integer(1, 1 << 20));
  if (root.has("filter_window_rows"))
    spec.set_filter_window_rows(root["filter_window_rows"].integer(kMinFilterWindowRows, 16384));
  if (!stagesOf(spec.pipeline()).interpolate) {
    spec.set_keyframe_interval(1);
    spec.set_keyframe_reason("k = 1: the pipeline does not interpolate");
    return;
  }
  readRerenderBound(root);
  const auto interval = root.optional("keyframe_interval");
  if (interval && !(interval->isString() && interval->string() == "auto")) {
    spec.set_keyframe_interval(interval->integer(1, 1000));
    spec.set_keyframe_reason("k = " + std::to_string(spec.keyframe_interval()) + ": given in the shot file");
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
  // 0 (the default, or "auto"): sized to the window by the renderer.
  const bool countGiven = root.has("bootstrap_samples") && !root["bootstrap_samples"].isString();
  if (root.has("bootstrap_samples") && !countGiven && root["bootstrap_samples"].string() != "auto")
    root["bootstrap_samples"].fail("must be a count or \"auto\"");
  spec.set_bootstrap_samples(countGiven ? root["bootstrap_samples"].integer(1, 1 << 30) : 0);
}

void readEvaluationKeys(const JsonNode& root, ShotSpec& spec) {
  if (!root.has("reference_spp")) {
    spec.set_reference_spp(0);
  } else if (root["reference_spp"].isString()) {
    if (root["reference_spp"].string() != "auto")
      root["reference_spp"].fail("expected a number of samples or \"auto\"");
    spec.set_reference_spp(kAutoReferenceSpp);  // chosen by withReferenceChosen once the pipeline is known
  } else {
    spec.set_reference_spp(root["reference_spp"].integer(1, 1 << 24));
  }
  if (root.has("baseline_core_seconds")) spec.set_baseline_core_seconds(root["baseline_core_seconds"].number(1e-9, 1e12));
  if (root.has("baseline_repeats")) spec.set_baseline_repeats(root["baseline_repeats"].integer(1, kMaxBaselineRepeats));
  if (auto frames = root.optional("evaluation_frames")) {
    for (const JsonNode& frame : frames->elements()) {
      const int64_t value = frame.integer(0, 10'000'000);
      if (value < spec.frame_start() || value > spec.frame_end()) frame.fail("not a frame of the shot");
      spec.add_evaluation_frames(value);
    }
  } else if (spec.pipeline() != PIPELINE_PT || spec.reference_spp() != 0) {
    for (const int64_t frame : defaultEvaluationFrames(spec)) spec.add_evaluation_frames(frame);
  }
}

// The keys of the spec's pipeline: its decomposition, resolved here once so that every
// worker splits the frames the same way (filtering pipelines split by default into what
// the scene can produce), and its filtering, gradient or Metropolis settings.
void readPipelineKeys(const JsonNode& root, const Scene& scene, ShotSpec& spec) {
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
  if (filtering) readFilteringKeys(root, spec);
  if (spec.pipeline() == PIPELINE_TGPT) readGradientKeys(root, spec);
  if (isMetropolisPipeline(spec.pipeline())) readMetropolisKeys(root, scene, spec);
}

// Every key a shot file may have: those all pipelines share, and each pipeline's own.
std::vector<const char*> shotFileKeys() {
  std::vector<const char*> keys = {"name", "scene", "frames", "resolution", "spp", "max_depth", "pipeline", "tile",
                                   "output", "priority", "max_attempts", "decompose", "reference_spp",
                                   "reference_cache", "evaluation_frames", "baseline_core_seconds", "baseline_repeats", "required_tags",
                                   "max_workers", "preview_every"};
  for (const PipelineTraits& traits : allPipelines())
    for (const std::string_view key : traits.keys)  // literals: terminated
      if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key.data());
  return keys;
}

Pipeline namedPipeline(const JsonNode& root) {
  if (!root.has("pipeline")) return PIPELINE_AUTO;
  const std::string name = root["pipeline"].string();
  const auto pipeline = pipelineNamed(name);
  if (!pipeline) root["pipeline"].fail("unknown pipeline \"" + name + "\" (this farm runs: " + pipelineNames() + ")");
  return *pipeline;
}

// The scene, loaded, and what the shot takes from it: frames, resolution, samples, depth.
std::shared_ptr<const Scene> readSceneKeys(const JsonNode& root, const std::filesystem::path& folder, ShotSpec& spec) {
  const JsonNode sceneKey = root["scene"];
  const std::filesystem::path scenePath = (folder / sceneKey.string()).lexically_normal();
  const auto scene = std::make_shared<const Scene>(loadScene(scenePath));  // throws SceneError naming the scene file
  spec.set_scene(scenePath.string());
  spec.set_frame_start(scene->defaults.frameStart);
  spec.set_frame_end(scene->defaults.frameEnd);
  if (auto frames = root.optional("frames")) {
    frames->expectKeys({"start", "end"});
    spec.set_frame_start((*frames)["start"].integer(0, 10'000'000));
    spec.set_frame_end((*frames)["end"].integer(static_cast<int>(spec.frame_start()), 10'000'000));
  }
  spec.set_width(scene->defaults.width);
  spec.set_height(scene->defaults.height);
  if (auto resolution = root.optional("resolution")) {
    const auto e = resolution->elements();
    if (e.size() != 2) resolution->fail("expected [width, height]");
    spec.set_width(e[0].integer(1, 16384));
    spec.set_height(e[1].integer(1, 16384));
  }
  spec.set_spp(root.has("spp") ? root["spp"].integer(1, 1 << 20) : scene->defaults.spp);
  spec.set_max_depth(root.has("max_depth") ? root["max_depth"].integer(0, 1024) : scene->defaults.maxDepth);
  return scene;
}

}  // namespace

double ShotFile::rerenderBound() const { return readRerenderBound(root()); }

ShotFile ShotFile::load(const std::filesystem::path& file) { return parse(readShotFileText(file), file); }

ShotFile ShotFile::parse(std::string_view text, const std::filesystem::path& file) {
  ShotFile shot;
  const std::string label = file.string();
  shot.text_ = std::make_shared<const Text>(Text{label, parseJsonDocument(text, label)});
  const JsonNode root = shot.root();
  root.expectKeys(shotFileKeys());
  const std::filesystem::path folder = std::filesystem::absolute(file).parent_path();

  ShotSpec& spec = shot.common_;
  spec.set_name(root.has("name") ? root["name"].string() : file.stem().string());
  const Pipeline named = namedPipeline(root);
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
  spec.set_preview_every(root.has("preview_every") ? root["preview_every"].integer(1, 1000) : 1);
  spec.set_output((folder / (root.has("output") ? root["output"].string() : "output/" + spec.name()))
                      .lexically_normal()
                      .string());
  if (root.has("reference_cache"))
    shot.referenceCache_ = (folder / root["reference_cache"].string()).lexically_normal();
  if (named != PIPELINE_NOOP) shot.scene_ = readSceneKeys(root, folder, spec);
  shot.named_ = shot.specAs(named);
  return shot;
}

ShotSpec ShotFile::specAs(Pipeline pipeline) const {
  const JsonNode root = this->root();
  ShotSpec spec = common_;
  spec.set_pipeline(pipeline);
  if (pipeline == PIPELINE_NOOP) {
    spec.set_noop_tasks(root["noop_tasks"].integer(1, 10'000'000));
    return spec;
  }
  if (!scene_) root["pipeline"].fail("a noop shot reads only as noop");
  if (pipeline == PIPELINE_AUTO) {
    // The rest depends on the pipeline the probe chooses (pipeline_probe.h). Its
    // candidates' keys are checked now, so that a bad one is refused before any probe runs.
    for (const Pipeline candidate : {PIPELINE_DUI, PIPELINE_TGPT}) {
      ShotSpec checked = spec;
      checked.set_pipeline(candidate);
      readPipelineKeys(root, *scene_, checked);
    }
  } else {
    readPipelineKeys(root, *scene_, spec);
  }
  readEvaluationKeys(root, spec);
  return spec;
}

std::string readShotFileText(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw SceneError(file.string() + ": cannot open the shot file");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace pathfarm::farm
