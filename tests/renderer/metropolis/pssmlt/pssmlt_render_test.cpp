// PSSMLT over windows of frames against the path tracer, and its hard inputs.
#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <sstream>

#include "renderer/integrators/frame_renderer.h"
#include "renderer/metropolis/metropolis_renderer.h"
#include "test_support.h"
#include "tests/renderer/metropolis/metropolis_test_support.h"
#include "tests/renderer/metropolis/render_error.h"

namespace pathfarm {
namespace {

constexpr int kSize = test_support::kMetropolisTestSize;

MetropolisSettings smallSettings(double mutationsPerPixel) {
  return test_support::smallMetropolisSettings(MetropolisMethod::Pssmlt, mutationsPerPixel);
}

RenderSettings referenceSettings(int spp) {
  RenderSettings settings;
  settings.width = settings.height = kSize;
  settings.maxDepth = 4;
  settings.spp = spp;
  return settings;
}

using test_support::pathTracedRelMse;
using test_support::relMse;

double meanOf(const FrameImage& image) {
  double sum = 0;
  for (const char* c : {"R", "G", "B"})
    for (float v : image.channel(c)) sum += v;
  return sum / (3.0 * static_cast<double>(image.pixelCount()));
}

bool allFinite(const std::vector<FrameImage>& frames) {
  for (const FrameImage& f : frames)
    for (const char* c : {"R", "G", "B"})
      for (float v : f.channel(c))
        if (!std::isfinite(v)) return false;
  return true;
}

TEST(Pssmlt, ConvergesToThePathTracedReferenceOfAnAnimatedScene) {
  const Scene scene = loadScene(test_support::sourceDir() / "scenes/cornell/scene.json");
  const FrameWindow window{10, 2};
  const int referenceSpp = 1024;
  const FrameRenderer reference(scene, referenceSettings(referenceSpp));
  std::vector<FrameImage> references;
  for (int64_t f = window.first; f < window.end(); ++f) references.push_back(reference.render(f));

  const double coarseBudget = 16, fineBudget = 128;
  const auto errorAt = [&](double mutations) {
    const std::vector<FrameImage> frames = MetropolisRenderer(scene, smallSettings(mutations)).render(window);
    double error = 0;
    for (size_t f = 0; f < frames.size(); ++f) error += relMse(frames[f], references[f]) / 2;
    return error;
  };
  const double coarse = errorAt(coarseBudget), fine = errorAt(fineBudget);
  double pathTraced = 0, referenceOwn = 0;
  for (const FrameImage& r : references) {
    pathTraced += pathTracedRelMse(r, referenceSpp, fineBudget) / 2;
    referenceOwn += pathTracedRelMse(r, referenceSpp, referenceSpp) / 2;
  }
  // Eight times the mutations: the error falls well below its coarse value.
  EXPECT_LT(fine, 0.5 * coarse) << coarse << " " << fine;
  // Metropolis spends its samples unevenly and in correlated chains; on this easy scene
  // it stays within 8x the error of path tracing with as many samples (plus the
  // reference's own noise).
  EXPECT_LT(fine, 8 * pathTraced + 2 * referenceOwn) << "path traced " << pathTraced;
}

TEST(Pssmlt, BitsDoNotDependOnThreadsOrTheSplitIntoTasks) {
  const Scene scene = loadScene(test_support::sourceDir() / "scenes/cornell/scene.json");
  const FrameWindow window{3, 2};
  MetropolisSettings settings = smallSettings(4);
  settings.tuneDelta = true;
  settings.threads = 1;
  const std::vector<FrameImage> oneThread = MetropolisRenderer(scene, settings).render(window);

  settings.threads = 2;
  const std::string pool = MetropolisRenderer(scene, settings).seedPool(window).serialize();
  std::vector<BlockResult> blocks;
  for (int b = 0; b < 4; ++b)  // four tasks, each its own renderer, as separate processes would be
    blocks.push_back(MetropolisRenderer(scene, settings).runBlock(window, SeedPool::parse(pool), b));
  const std::vector<FrameImage> fourTasks =
      MetropolisRenderer(scene, settings).merge(window, SeedPool::parse(pool), std::move(blocks));
  for (size_t f = 0; f < oneThread.size(); ++f)
    for (const char* c : {"R", "G", "B"}) EXPECT_EQ(oneThread[f].channel(c), fourTasks[f].channel(c));
  EXPECT_GT(meanOf(oneThread[0]), 0);
}

// A closed room with a light: frames of a static scene agree, one-frame windows and an
// always-open shutter work, and the mean matches the path tracer.
Scene roomScene(const std::string& shutter) {
  return test_support::sceneFromJson(R"({
    "camera": {"position": [0, 1, 2.5], "look_at": [0, 1, 0], "fov": 60, "shutter": )" + shutter + R"(},
    "materials": {"white": {"type": "diffuse", "reflectance": 0.6}},
    "shapes": [
      {"type": "box", "size": [3, 3, 6], "material": "white", "transform": {"translate": [0, 1, 0]}},
      {"type": "rectangle", "size": [0.6, 0.6], "material": "white", "emission": 8,
       "transform": {"translate": [0, 2.45, 0], "rotate": {"axis": [1, 0, 0], "angle": 90}}}]
  })");
}

// Each frame's image mean with its standard error, from the spread of the blocks' own
// estimates (independent chains; the shared normalization cancels between frames).
std::vector<test_support::MeanEstimate> frameMeans(const Scene& scene, const MetropolisSettings& settings,
                                                   FrameWindow window) {
  const MetropolisRenderer renderer(scene, settings);
  const SeedPool pool = renderer.seedPool(window);
  const int blocks = renderer.blocks();
  std::vector<std::vector<double>> perBlock(static_cast<size_t>(window.count));
  for (int b = 0; b < blocks; ++b) {
    const BlockResult result = renderer.runBlock(window, pool, b);
    for (size_t f = 0; f < perBlock.size(); ++f) perBlock[f].push_back(meanOf(result.frames[f]) * blocks);
  }
  std::vector<test_support::MeanEstimate> means;
  for (const std::vector<double>& values : perBlock) {
    double sum = 0, sumSquares = 0;
    for (double v : values) sum += v;
    const double mean = sum / blocks;
    for (double v : values) sumSquares += (v - mean) * (v - mean);
    means.push_back({mean, std::sqrt(sumSquares / (blocks - 1) / blocks)});
  }
  return means;
}

// A closed room lit from the ceiling, static: every frame of a window has the path
// tracer's image mean, also for a one-frame window and an always-open shutter. The
// bounds are 6 standard errors (8 blocks: Student's t with 7 degrees of freedom stays
// below 6 with probability 0.9995).
TEST(Pssmlt, HardInputsStaticSceneOneFrameWindowAndAlwaysOpenShutter) {
  MetropolisSettings settings = smallSettings(48);
  settings.chainsPerBlock = 4;  // 8 blocks
  for (const char* shutter : {"[0, 0.5]", "[0, 1]"}) {
    const Scene scene = roomScene(shutter);
    const FrameImage reference = FrameRenderer(scene, referenceSettings(256)).render(0);
    double pathTraced = 0, pathTracedVariance = 0;
    for (const char* c : {"R", "G", "B"}) {
      const test_support::MeanEstimate m = test_support::meanOverPixels(reference, c);
      pathTraced += m.mean / 3;
      pathTracedVariance += m.standardError * m.standardError / 3;  // channels are close to equal: a safe upper bound
    }
    for (FrameWindow window : {FrameWindow{0, 3}, FrameWindow{7, 1}}) {
      for (const test_support::MeanEstimate& m : frameMeans(scene, settings, window)) {
        ASSERT_TRUE(std::isfinite(m.mean));
        EXPECT_NEAR(m.mean, pathTraced, 6 * std::sqrt(m.standardError * m.standardError + pathTracedVariance))
            << shutter << " window of " << window.count;
      }
    }
  }
}

TEST(Pssmlt, ZeroLengthShutterIsAClearError) {
  Scene scene = roomScene("[0.3, 0.6]");
  scene.camera.shutterClose = scene.camera.shutterOpen;  // the scene loader refuses it; the API must too
  const MetropolisRenderer renderer(scene, smallSettings(4));
  try {
    renderer.render({0, 2});
    FAIL() << "rendered with a shutter of zero length";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("zero length"), std::string::npos) << e.what();
  }
}

TEST(Pssmlt, UnreachableLightGivesBlackFramesAndAWarning) {
  const Scene scene = test_support::sealedLightScene();
  std::ostringstream log;
  const auto previous = spdlog::default_logger();
  spdlog::set_default_logger(std::make_shared<spdlog::logger>("capture", std::make_shared<spdlog::sinks::ostream_sink_mt>(log)));
  const std::vector<FrameImage> frames = MetropolisRenderer(scene, smallSettings(4)).render({0, 2});
  spdlog::set_default_logger(previous);
  ASSERT_TRUE(allFinite(frames));
  for (const FrameImage& f : frames) EXPECT_EQ(meanOf(f), 0);
  EXPECT_NE(log.str().find("carried light"), std::string::npos) << log.str();
}

}  // namespace
}  // namespace pathfarm
