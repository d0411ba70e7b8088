#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>

#include "renderer/scene/json_node.h"
#include "scheduler/planner.h"
#include "client/shot_preparation.h"
#include "test_support.h"

namespace pathfarm::farm {
namespace {

// Shot files in a temporary folder that links to the demo scene's folder, so relative
// scene paths are resolved against the shot file's own folder as in real use.
std::filesystem::path writeShot(const std::string& name, const std::string& json) {
  const auto folder = test_support::processTemporaryFolder("pathfarm_shot_files");
  std::filesystem::create_directories(folder);
  // A link left by another checkout points elsewhere: replace it.
  const auto target = test_support::sourceDir() / "scenes/cornell";
  std::error_code error;
  if (std::filesystem::read_symlink(folder / "cornell", error) != target) {
    std::filesystem::remove(folder / "cornell", error);
    std::filesystem::create_directory_symlink(target, folder / "cornell", error);
  }
  const auto file = folder / ("test_" + name + ".json");
  std::ofstream(file) << json;
  return file;
}

std::string readText(const std::filesystem::path& file) {
  std::ifstream in(file);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::string errorOf(const std::string& json) {
  const auto file = writeShot("bad", json);
  std::string message = "(no error)";
  try {
    loadShotFile(file);
  } catch (const SceneError& e) {
    message = e.what();
  }
  std::filesystem::remove(file);
  return message;
}

TEST(ShotFile, FillsDefaultsFromTheSceneAndMakesPathsAbsolute) {
  const auto file = writeShot("defaults", R"({"scene": "cornell/scene.json", "frames": {"start": 3, "end": 5}, "tile": 16,
    "pipeline": "dui"})");
  const ShotSpec spec = loadShotFile(file);
  std::filesystem::remove(file);
  EXPECT_EQ(spec.name(), "test_defaults");
  // The filtering pipelines split into what the scene can produce, and measure the middle pair.
  EXPECT_EQ(spec.decompose(), "diffuse_direct=ED,diffuse_indirect=ED.+,reflection=ERD.*,transmission=ETTD.*,residual");
  EXPECT_EQ(spec.evaluation_frames_size(), 2);
  EXPECT_EQ(spec.evaluation_frames(0), 4);
  EXPECT_EQ(spec.reference_spp(), 0);
  // Three frames allow only k = 2, which the probe accepts or refuses with its prediction
  // (and with k = 1 dui runs as d).
  EXPECT_TRUE(spec.keyframe_interval() == 1 || spec.keyframe_interval() == 2);
  EXPECT_EQ(spec.pipeline(), spec.keyframe_interval() == 2 ? PIPELINE_DUI : PIPELINE_D);
  EXPECT_NE(spec.keyframe_reason().find("k = 2: "), std::string::npos) << spec.keyframe_reason();
  EXPECT_EQ(spec.scene(), (file.parent_path() / "cornell/scene.json").string());
  EXPECT_EQ(spec.frame_start(), 3);
  EXPECT_EQ(spec.frame_end(), 5);
  EXPECT_EQ(spec.width(), 256);  // the scene's render defaults
  EXPECT_EQ(spec.spp(), 64);
  EXPECT_EQ(spec.max_depth(), 8);
  EXPECT_EQ(spec.tile(), 16);
  EXPECT_EQ(spec.max_attempts(), 3);
  EXPECT_TRUE(std::filesystem::path(spec.output()).is_absolute());
}

TEST(ShotFile, BadShotsAreRefusedWithFileAndKey) {
  EXPECT_NE(errorOf(R"({"scene": "cornell/scene.json", "pipeline": "dui2"})").find("pipeline: unknown pipeline \"dui2\""),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"scene": "cornell/nowhere.json"})").find("nowhere.json: cannot open the scene file"),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"scene": "cornell/scene.json", "tiles": 5})").find("tiles: unknown key"), std::string::npos);
  EXPECT_NE(errorOf(R"({"scene": "cornell/scene.json", "frames": {"start": 4, "end": 1}})").find("frames.end"),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"scene": "cornell/scene.json", "tile": 2})").find("tile: 2 is out of range"), std::string::npos);
  EXPECT_NE(errorOf(R"({"scene": )").find("invalid JSON"), std::string::npos);
  EXPECT_NE(errorOf(R"({"scene": "cornell/scene.json", "spp": 1e400})").find("invalid JSON"), std::string::npos);
  EXPECT_NE(errorOf(R"({"scene": "cornell/scene.json", "decompose": "x=E(D"})").find("decompose: light-path expression"),
            std::string::npos);
}

// Found with the shot_json fuzz target: 100 bytes of shot file made the reader plan 10^13
// tasks (it hung, then ran out of memory). A shot too large for a default scheduler is
// read without being planned; the scheduler refuses it or plans it within its limits.
TEST(ShotFile, AShotTooLargeToPlanIsReadWithoutPlanningIt) {
  const auto file = writeShot("huge", R"({"scene": "cornell/scene.json", "pipeline": "pt", "tile": 8,
    "frames": {"start": 0, "end": 10000000}, "resolution": [16384, 16384]})");
  const ShotSpec spec = loadShotFile(file);
  std::filesystem::remove(file);
  EXPECT_EQ(spec.frame_end(), 10'000'000);
  EXPECT_EQ(spec.tile(), 8);
  EXPECT_GT(plannedTasksAtLeast(spec), ShotLimits{}.maxTasks);
  EXPECT_THROW(planShotWithin(spec, ShotLimits{}), PlanError);
}

TEST(ShotFile, ReadsTheFilteringAndEvaluationKeys) {
  const auto file = writeShot("filtering", R"({"scene": "cornell/scene.json", "pipeline": "di", "keyframe_interval": 3,
    "reference_spp": 512, "evaluation_frames": [2, 7], "baseline_core_seconds": 4.5, "baseline_repeats": 4})");
  const ShotSpec spec = loadShotFile(file);
  std::filesystem::remove(file);
  EXPECT_EQ(spec.keyframe_interval(), 3);
  EXPECT_EQ(spec.keyframe_reason(), "k = 3: given in the shot file");
  EXPECT_EQ(spec.reference_spp(), 512);
  ASSERT_EQ(spec.evaluation_frames_size(), 2);
  EXPECT_EQ(spec.evaluation_frames(1), 7);
  EXPECT_EQ(spec.baseline_core_seconds(), 4.5);
  EXPECT_EQ(spec.baseline_repeats(), 4);
  const auto tooMany = writeShot("repeats", R"({"scene": "cornell/scene.json", "baseline_repeats": 65})");
  try {
    loadShotFile(tooMany);
    ADD_FAILURE() << "65 baseline renders a frame were accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("baseline_repeats"), std::string::npos) << e.what();
  }
  std::filesystem::remove(tooMany);

  const auto du = writeShot("du", R"({"scene": "cornell/scene.json", "pipeline": "du", "keyframe_interval": 3})");
  EXPECT_EQ(loadShotFile(du).keyframe_interval(), 1);  // nothing is interpolated
  std::filesystem::remove(du);
  const auto pt = writeShot("pt", R"({"scene": "cornell/scene.json", "pipeline": "pt"})");
  EXPECT_EQ(loadShotFile(pt).decompose(), "none");
  EXPECT_EQ(loadShotFile(pt).evaluation_frames_size(), 0);  // nothing to measure without a reference
  std::filesystem::remove(pt);
}

TEST(ShotFile, WithoutAPipelineAProbeChoosesItAndTheFileReadsAsEachCandidate) {
  const std::string text = R"({"scene": "cornell/scene.json", "frames": {"start": 0, "end": 9},
    "resolution": [64, 64], "spp": 8, "keyframe_interval": 3, "poisson_window": 6})";
  const auto file = writeShot("auto", text);
  const ShotSpec spec = loadShotFile(file);
  std::filesystem::remove(file);
  EXPECT_EQ(spec.pipeline(), PIPELINE_AUTO);
  // What every candidate shares is resolved; what depends on the pipeline is not.
  EXPECT_EQ(spec.width(), 64);
  EXPECT_EQ(spec.evaluation_frames_size(), 2);
  EXPECT_EQ(spec.decompose(), "");
  EXPECT_EQ(spec.keyframe_interval(), 0);
  EXPECT_THROW(planShot(spec), PlanError);  // the farm never runs "auto" itself
  const ShotFile read = ShotFile::parse(text, file);
  const ShotSpec dui = preparedShot(read, PIPELINE_DUI);
  EXPECT_EQ(dui.pipeline(), PIPELINE_DUI);
  EXPECT_EQ(dui.keyframe_interval(), 3);
  EXPECT_NE(dui.decompose(), "none");
  const ShotSpec tgpt = preparedShot(read, PIPELINE_TGPT);
  EXPECT_EQ(tgpt.poisson_window(), 6);
  EXPECT_EQ(tgpt.decompose(), "none");
  // A key only some candidate reads is still checked when the file is read.
  EXPECT_NE(errorOf(R"({"scene": "cornell/scene.json", "poisson_norm": "l3"})").find("poisson_norm"), std::string::npos);
  EXPECT_NE(errorOf(R"({"scene": "cornell/scene.json", "feature_spp": 0})").find("feature_spp"), std::string::npos);
  EXPECT_NE(errorOf(R"({"scene": "cornell/scene.json", "filter_window_rows": 8})").find("filter_window_rows"),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"scene": "cornell/scene.json", "rerender_spp": 0})").find("rerender_spp"), std::string::npos);
}

TEST(ShotFile, FilterWindowRowsAreReadForTheFilteringPipelines) {
  const auto file = writeShot("windows", R"({"scene": "cornell/scene.json", "pipeline": "dui", "resolution": [64, 200],
    "filter_window_rows": 64})");
  const ShotSpec spec = loadShotFile(file);
  std::filesystem::remove(file);
  EXPECT_EQ(spec.filter_window_rows(), 64);
  const std::vector<RowWindow> windows = filterWindowsOf(spec);  // 200 rows in four windows of 50
  ASSERT_EQ(windows.size(), 4u);
  EXPECT_EQ(windows.front().first, 0);
  EXPECT_EQ(windows[1].first, 50);
  EXPECT_EQ(windows.back().end, 200);
}

// The sparse re-render takes spp, or what the file asks up to spp; keyframes beside an
// upsampling pipeline's re-render take a quarter of spp.
TEST(ShotFile, TheRerenderSamplesAreSppOrTheFilesAtMostSpp) {
  const auto read = [](const std::string& keys) {
    const auto file = writeShot("rerender", R"({"scene": "cornell/scene.json", "spp": 256, )" + keys + "}");
    const ShotSpec spec = loadShotFile(file);
    std::filesystem::remove(file);
    return spec;
  };
  EXPECT_EQ(rerenderSppOf(read(R"("pipeline": "dui", "keyframe_interval": 2)")), 256);
  EXPECT_EQ(rerenderSppOf(read(R"("pipeline": "du", "rerender_spp": 128)")), 128);
  EXPECT_EQ(keyframeSppOf(read(R"("pipeline": "di", "keyframe_interval": 2)")), 256);
  EXPECT_EQ(keyframeSppOf(read(R"("pipeline": "dui", "keyframe_interval": 2)")), 64);
  EXPECT_EQ(rerenderSppOf(read(R"("pipeline": "dui", "keyframe_interval": 2, "rerender_spp": 40)")), 40);
  EXPECT_EQ(rerenderSppOf(read(R"("pipeline": "di", "keyframe_interval": 2, "rerender_spp": 1000)")), 256);
  ShotSpec one;  // a quarter of 1 spp is still a sample
  one.set_pipeline(PIPELINE_DUI);
  one.set_spp(1);
  EXPECT_EQ(keyframeSppOf(one), 1);
}

// Every height and window size: the windows cover the frame's rows once each, top to
// bottom, their borders on even rows (a half-resolution denoise's windows are whole rows),
// each at most one row more than asked, their heights within two rows of each other.
TEST(ShotFile, FilterWindowsCoverTheFrameWithBordersOnEvenRows) {
  ShotSpec spec;
  for (const int rows : {16, 17, 33, 50, 512})
    for (int height = 1; height <= 700; ++height) {
      spec.set_height(height);
      spec.set_filter_window_rows(rows);
      const std::vector<RowWindow> windows = filterWindowsOf(spec);
      ASSERT_FALSE(windows.empty());
      int covered = 0, shortest = height, tallest = 0;
      for (const RowWindow& window : windows) {
        ASSERT_EQ(window.first, covered) << height << " rows in windows of " << rows;
        ASSERT_GT(window.end, window.first) << height << " rows in windows of " << rows;
        if (window.end != height) {
          ASSERT_EQ(window.end % 2, 0) << height << " rows in windows of " << rows;
        }
        ASSERT_LE(window.end - window.first, rows + 1) << height << " rows in windows of " << rows;
        shortest = std::min(shortest, window.end - window.first);
        tallest = std::max(tallest, window.end - window.first);
        covered = window.end;
      }
      ASSERT_EQ(covered, height);
      ASSERT_LE(tallest - shortest, 2) << height << " rows in windows of " << rows;
    }
}

TEST(ShotFile, ReadingRunsNoProbeAndPreparingRunsTheKeyframeProbe) {
  const auto file = writeShot("probe-later", R"({"scene": "cornell/scene.json", "frames": {"start": 0, "end": 4},
    "resolution": [64, 64], "spp": 8, "pipeline": "dui", "keyframe_interval": "auto"})");
  const ShotFile read = ShotFile::load(file);
  std::filesystem::remove(file);
  EXPECT_EQ(read.spec().keyframe_interval(), 0);  // left to the probe
  EXPECT_EQ(read.spec().keyframe_reason(), "");
  const ShotSpec prepared = preparedShot(read);
  EXPECT_GE(prepared.keyframe_interval(), 1);
  EXPECT_NE(prepared.keyframe_reason().find("k = "), std::string::npos) << prepared.keyframe_reason();
}

TEST(ShotFile, DuiWhoseProbeChoosesNoIntervalRunsAsDenoisingAlone) {
  // A re-render bound of 0 refuses every interval the probe tries: k = 1.
  const auto chosen = writeShot("dui-k1", R"({"scene": "cornell/scene.json", "frames": {"start": 0, "end": 4},
    "resolution": [64, 64], "spp": 8, "pipeline": "dui", "rerender_bound": 0})");
  const ShotSpec spec = loadShotFile(chosen);
  std::filesystem::remove(chosen);
  EXPECT_EQ(spec.keyframe_interval(), 1) << spec.keyframe_reason();
  EXPECT_EQ(spec.pipeline(), PIPELINE_D);
  EXPECT_NE(spec.pipeline_reason().find("asked for dui"), std::string::npos) << spec.pipeline_reason();
  // k = 1 given in the shot file is the user's word: dui stays dui.
  const auto given = writeShot("dui-given-k1", R"({"scene": "cornell/scene.json", "frames": {"start": 0, "end": 4},
    "resolution": [64, 64], "spp": 8, "pipeline": "dui", "keyframe_interval": 1})");
  const ShotSpec kept = loadShotFile(given);
  std::filesystem::remove(given);
  EXPECT_EQ(kept.pipeline(), PIPELINE_DUI);
  EXPECT_EQ(kept.pipeline_reason(), "");
}

TEST(ShotFile, AStaticSceneGetsTheLongestKeyframeIntervalTheProbeTries) {
  // The demo scene without its animations: nothing moves, little needs re-rendering.
  nlohmann::json scene = nlohmann::json::parse(readText(test_support::sourceDir() / "scenes/cornell/scene.json"));
  for (auto& shape : scene["shapes"]) shape.erase("animation");
  const auto folder = writeShot("static-scene-folder", "{}").parent_path();
  std::ofstream(folder / "static_scene.json") << scene.dump();
  const auto file = writeShot("static", R"({"scene": "static_scene.json", "frames": {"start": 0, "end": 11},
    "resolution": [64, 64], "spp": 8, "pipeline": "dui"})");
  const ShotSpec spec = loadShotFile(file);
  std::filesystem::remove(file);
  EXPECT_EQ(spec.keyframe_interval(), 8) << spec.keyframe_reason();
  // Only the edges of the spheres, where samples see a specular chain the pixel centre
  // does not, count as untracked at the probe's 16x16.
  EXPECT_EQ(spec.keyframe_reason().rfind("k = 8: the largest interval", 0), 0u) << spec.keyframe_reason();
}

TEST(ShotFile, ReadsTheGradientDomainKeys) {
  const auto file = writeShot("tgpt", R"({"scene": "cornell/scene.json", "pipeline": "tgpt", "poisson_window": 6,
    "poisson_overlap": 3})");
  const ShotSpec spec = loadShotFile(file);
  std::filesystem::remove(file);
  EXPECT_EQ(spec.poisson_window(), 6);
  EXPECT_EQ(spec.poisson_overlap(), 3);
  EXPECT_EQ(spec.poisson_norm(), "l1");
  EXPECT_EQ(spec.decompose(), "none");
  EXPECT_EQ(spec.evaluation_frames_size(), 2);  // the baseline's cost is measured
  EXPECT_NE(errorOf(R"({"scene": "cornell/scene.json", "pipeline": "tgpt", "poisson_window": 4, "poisson_overlap": 4})")
                .find("poisson_overlap: 4 is out of range"),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"scene": "cornell/scene.json", "pipeline": "tgpt", "poisson_norm": "l3"})").find("poisson_norm"),
            std::string::npos);
}

TEST(ShotFile, ReadsTheMetropolisKeysAndRefusesAClosedShutter) {
  const auto file = writeShot("tmlt", R"({"scene": "cornell/scene.json", "pipeline": "tmlt", "spp": 32, "mlt_window": 6,
    "mlt_chains": 12, "chains_per_block": 5, "chain_tasks": 2, "temporal_delta": 0.5, "tune_delta": true})");
  const ShotSpec spec = loadShotFile(file);
  std::filesystem::remove(file);
  EXPECT_EQ(spec.mlt_window(), 6);
  EXPECT_EQ(spec.mutations_per_pixel(), 32);  // the shot's spp when not given
  EXPECT_EQ(spec.mlt_chains(), 12);
  EXPECT_EQ(spec.chains_per_block(), 5);
  EXPECT_EQ(spec.chain_tasks(), 2);
  EXPECT_EQ(spec.temporal_delta(), 0.5);
  EXPECT_TRUE(spec.tune_delta());
  EXPECT_EQ(spec.decompose(), "none");
  EXPECT_EQ(spec.bootstrap_samples(), 0);  // sized to the window by the renderer

  nlohmann::json scene = nlohmann::json::parse(readText(test_support::sourceDir() / "scenes/cornell/scene.json"));
  scene["camera"].erase("shutter");  // no shutter: open for no time
  const auto folder = writeShot("closed-shutter-folder", "{}").parent_path();
  std::ofstream(folder / "closed_shutter_scene.json") << scene.dump();
  EXPECT_NE(errorOf(R"({"scene": "closed_shutter_scene.json", "pipeline": "pssmlt"})").find("zero length"),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"scene": "cornell/scene.json", "pipeline": "mlt", "mlt_chains": 0})").find("mlt_chains"),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"scene": "cornell/scene.json", "pipeline": "tmlt", "bootstrap_samples": "many"})")
                .find("bootstrap_samples: must be a count or \"auto\""),
            std::string::npos);
  for (const auto& [value, expected] : {std::pair{"\"auto\"", 0}, std::pair{"5000", 5000}}) {
    const auto counted = writeShot("bootstrap", std::string(R"({"scene": "cornell/scene.json", "pipeline": "tmlt", )") +
                                                    R"("bootstrap_samples": )" + value + "}");
    EXPECT_EQ(loadShotFile(counted).bootstrap_samples(), expected) << value;
    std::filesystem::remove(counted);
  }
}

TEST(ShotFile, BadFilteringShotsAreRefused) {
  EXPECT_NE(errorOf(R"({"scene": "cornell/scene.json", "keyframe_interval": 0})").find("keyframe_interval: 0 is out of range"),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"scene": "cornell/scene.json", "keyframe_interval": "often"})").find("keyframe_interval"),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"scene": "cornell/scene.json", "evaluation_frames": [99]})").find("evaluation_frames[0]: not a frame of the shot"),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"scene": "cornell/scene.json", "decompose": "none"})").find("decompose: the filtering pipelines need"),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"scene": "cornell/scene.json", "pipeline": "du", "resolution": [65, 64]})").find("even width and height"),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"scene": "cornell/scene.json", "rerender_bound": 2})").find("rerender_bound"), std::string::npos);
}

TEST(ShotFile, ResolvesTheDecompositionOnceForEveryWorker) {
  const auto file = writeShot("split", R"({"scene": "cornell/scene.json", "pipeline": "pt", "decompose": "default"})");
  EXPECT_EQ(loadShotFile(file).decompose(),
            "diffuse_direct=ED,diffuse_indirect=ED.+,reflection=ERD.*,transmission=ETTD.*,residual");
  std::filesystem::remove(file);
}

// The shot files shipped beside the scenes (README's commands name them) load as they are.
TEST(ShotFile, EveryShippedShotFileLoads) {
  int shots = 0;
  for (const auto& folder : std::filesystem::directory_iterator(test_support::sourceDir() / "scenes")) {
    const auto file = folder.path() / "shot.json";
    if (!std::filesystem::exists(file)) continue;
    ++shots;
    try {
      const ShotSpec spec = loadShotFile(file);
      EXPECT_GE(spec.keyframe_interval(), 1) << file;
      EXPECT_GT(spec.reference_spp(), 0) << file << ": a shipped shot measures itself";
    } catch (const std::exception& e) {
      ADD_FAILURE() << file << ": " << e.what();
    }
  }
  EXPECT_GE(shots, 5);
}

}  // namespace
}  // namespace pathfarm::farm
