// Gradient-domain rendering against independent answers: a scene of constant radiance
// has no differences, the reconstruction's mean is the path tracer's, temporal offsets
// of a still scene replay their base samples exactly, and the bits do not depend on
// threads or tiles, nor on windows rendered apart and joined.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

#include "postproc/poisson/screened_poisson.h"
#include "renderer/integrators/gradient_estimates.h"
#include "renderer/integrators/gradient_frame_renderer.h"
#include "test_support.h"
#include "renderer/scene/scene_loader.h"
#include "tests/renderer/scene/gltf/gltf_arm.h"
#include "tests/renderer/sky_furnace.h"

namespace pathfarm {
namespace {

RenderSettings small(int width, int height, int spp, int maxDepth) {
  RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.spp = spp;
  settings.maxDepth = maxDepth;
  return settings;
}

// The path tracer's frame at `spp` samples with otherwise these settings: a reference.
FrameImage pathTraced(const Scene& scene, RenderSettings settings, int spp, int64_t frame) {
  settings.spp = spp;
  return FrameRenderer(scene, settings).render(frame);
}

// The mean of an estimate over `seeds` renders, from its sum and sum of squares, and the
// variance of that mean.
struct SeedMean {
  double mean, variance;
};

SeedMean overSeeds(double sum, double squares, int seeds) {
  const double mean = sum / seeds;
  return {mean, (squares - seeds * mean * mean) / (seeds - 1) / seeds};
}

TEST(GradientRender, ConstantRadianceSceneHasZeroDifferences) {
  // A wide diffuse floor under a uniform sky: every visible point has radiance
  // albedo * sky = 0.5, and every offset path sees what its base path sees.
  const Scene scene = test_support::sceneFromJson(R"({
    "camera": {"position": [0, 1, 0], "look_at": [0, 0, -1], "fov": 20},
    "environment": {"radiance": 1},
    "materials": {"floor": {"type": "diffuse", "reflectance": 0.5}},
    "shapes": [{"type": "rectangle", "size": [1000, 1000], "material": "floor",
                "transform": {"rotate": {"axis": [1, 0, 0], "angle": -90}}}]})");
  const FrameImage image = GradientFrameRenderer(scene, small(12, 10, 8, 4), {}).render(0);
  for (const char* c : {"R", "G", "B"}) {
    for (const std::string layer : {"gradient_x.", "gradient_y."})
      for (float g : image.channel(layer + c)) ASSERT_NEAR(g, 0.0f, 1e-5f) << layer << c;
    const auto mean = test_support::meanOverPixels(image, c);
    EXPECT_NEAR(mean.mean, 0.5, 5 * mean.standardError + 1e-6);
  }
}

// The sky furnace (sky_furnace.h) reconstructed as `pathfarm poisson` does (L2, then the
// directly seen emission added back): the sky reaches the frame only through
// direct_emission, the sphere's 0.5 through the primal and the differences. gpt renders
// one frame, tgpt a window of two with its temporal differences. Each region's mean over
// seeds must lie within 5 standard errors of the answer, measured from the seeds' spread:
// the differences' noise at the silhouette moves light between the regions, so the
// primal's own variance would understate the reconstruction's.
void expectGradientSkyFurnace(test_support::SkySource sky) {
  const int size = 24, seeds = 8;
  for (const bool temporal : {false, true}) {
    GradientSettings gradient;
    gradient.temporal = temporal;
    const std::string name = temporal ? "tgpt" : "gpt";
    const int frames = temporal ? 2 : 1;
    // Per frame and region (sphere, sky): sums over seeds of the region's mean and its square.
    double sum[2][2] = {}, squares[2][2] = {};
    for (int seed = 0; seed < seeds; ++seed) {
      const Scene scene = test_support::skyFurnaceScene(static_cast<uint64_t>(seed), sky);
      const GradientFrameRenderer renderer(scene, small(size, size, 16, 4), gradient);
      std::vector<GradientFrame> window;
      for (int64_t f = 0; f < frames; ++f) window.push_back(GradientFrame::fromImage(renderer.render(f), name));
      std::vector<const GradientFrame*> inputs;
      for (const GradientFrame& frame : window) inputs.push_back(&frame);
      const auto solved = reconstructWindow(inputs, PoissonSettings{});
      for (size_t f = 0; f < window.size(); ++f) {
        std::vector<float> green(window[f].pixelCount());  // the furnace is grey
        for (size_t p = 0; p < green.size(); ++p) green[p] = solved[f][1][p] + window[f].directEmission[1][p];
        const auto means = test_support::skyFurnaceMeans(size, size, green);
        for (const auto& [region, mean] : {std::pair{0, means.sphere.mean}, std::pair{1, means.sky.mean}}) {
          sum[f][region] += mean;
          squares[f][region] += mean * mean;
        }
      }
    }
    for (int f = 0; f < frames; ++f)
      for (const auto& [region, expected] :
           {std::pair{0, test_support::kSkyFurnaceSphere}, std::pair{1, test_support::kSkyFurnaceSky}}) {
        const auto [mean, variance] = overSeeds(sum[f][region], squares[f][region], seeds);
        EXPECT_NEAR(mean, expected, 5 * std::sqrt(variance)) << name << " frame " << f << " region " << region;
        EXPECT_GT(variance, 0) << name;
      }
  }
}

TEST(GradientRender, SkyFurnaceReconstructsAlbedoOnTheSphereAndOneOnTheSky) {
  expectGradientSkyFurnace(test_support::SkySource::Radiance);
}
TEST(GradientRender, SkyFurnaceUnderAConstantMap) { expectGradientSkyFurnace(test_support::SkySource::ConstantMap); }

// The demo Cornell box for statistics: looked at from lower down, so that the lamp is out
// of sight (the differences leave directly seen emitters out, the path tracer's image
// would not); a large lamp and a rough glass sphere, so that no pixel's mean hangs on
// rare caustic paths that a few seeds would not see. The mirror sphere stays. With
// `movingLamp`, the lamp slides 0.6 across the ceiling from frame 6 to frame 7, so that the
// light on the walls changes between those frames by much more than a few seeds' noise.
Scene cornellForStatistics(bool movingLamp = false) {
  std::ifstream file(test_support::sourceDir() / "scenes/cornell/scene.json");
  std::string json{std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
  std::vector<std::pair<std::string, std::string>> edits = {
      {"\"look_at\": [0, 1, 0]", "\"look_at\": [0, 0.3, 0]"},
      {"\"size\": [0.5, 0.4]", "\"size\": [1.4, 1.4]"},
      {"\"emission\": [17, 12, 4]", "\"emission\": [3, 2.4, 1]"},
      {"\"type\": \"dielectric\", \"ior\": 1.5", "\"type\": \"rough_dielectric\", \"alpha\": 0.3"}};
  if (movingLamp)
    edits.emplace_back("\"transform\": {\"translate\": [0, 1.985, 0], \"rotate\": {\"axis\": [1, 0, 0], \"angle\": 90}}",
                       "\"transform\": {\"translate\": [0, 1.985, 0], \"rotate\": {\"axis\": [1, 0, 0], \"angle\": 90}}, "
                       "\"animation\": {\"translate\": [{\"frame\": 6, \"value\": [-0.3, 1.985, 0]}, "
                       "{\"frame\": 7, \"value\": [0.3, 1.985, 0]}]}");
  for (const auto& [from, to] : edits) {
    const size_t at = json.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    json.replace(at, from.size(), to);
  }
  return test_support::sceneFromJson(json, test_support::sourceDir() / "scenes/cornell");
}

// The reconstruction's mean over each quadrant, over many seeds, against the path
// tracer's at many samples: the L2 reconstruction is linear in unbiased data.
TEST(GradientRender, L2ReconstructionIsUnbiased) {
  Scene scene = cornellForStatistics();
  const int w = 12, h = 12, seeds = 16;
  const RenderSettings settings = small(w, h, 8, 5);
  const FrameImage truth = pathTraced(scene, settings, 2048, 3);

  // quadrant q, channel c: the sum over seeds and of squares, per estimate.
  double sum[2][4][3] = {}, squares[2][4][3] = {};
  for (int seed = 0; seed < seeds; ++seed) {
    scene.seed = 1000 + static_cast<uint64_t>(seed);
    const FrameImage image = GradientFrameRenderer(scene, settings, {}).render(3);
    const GradientFrame frame = GradientFrame::fromImage(image, "gpt");
    const auto solved = reconstructWindow({&frame}, PoissonSettings{});
    for (size_t c = 0; c < 3; ++c) {
      double quadrant[2][4] = {};
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const size_t p = static_cast<size_t>(y * w + x);
          const int q = (x >= w / 2) + 2 * (y >= h / 2);
          quadrant[0][q] += (solved[0][c][p] + frame.directEmission[c][p]) / (w * h / 4);
          quadrant[1][q] += image.channel(kColorChannels[c])[p] / (w * h / 4);
        }
      for (int e = 0; e < 2; ++e)
        for (int q = 0; q < 4; ++q) {
          sum[e][q][c] += quadrant[e][q];
          squares[e][q][c] += quadrant[e][q] * quadrant[e][q];
        }
    }
  }
  for (size_t c = 0; c < 3; ++c) {
    const auto& ref = truth.channel(kColorChannels[c]);
    const auto& refVariance = truth.channel(std::string("variance.") + kColorChannels[c]);
    for (int q = 0; q < 4; ++q) {
      double refMean = 0, refVar = 0;
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          if ((x >= w / 2) + 2 * (y >= h / 2) == q) {
            refMean += ref[static_cast<size_t>(y * w + x)] / (w * h / 4);
            refVar += refVariance[static_cast<size_t>(y * w + x)] / (w * h / 4.0) / (w * h / 4.0);
          }
      for (int e = 0; e < 2; ++e) {  // the reconstruction, and the primal image
        const auto [mean, variance] = overSeeds(sum[e][q][c], squares[e][q][c], seeds);
        EXPECT_NEAR(mean, refMean, 5 * std::sqrt(variance + refVar) + 1e-6)
            << (e ? "primal" : "reconstruction") << ", quadrant " << q << ", channel " << c;
      }
    }
  }
}

// The temporal and mixed differences against converged path-traced images of both
// frames, compared through each pixel's correspondence. Per layer and channel, the test
// pools the pixels into one sum, each weighed by its expected difference (a matched
// filter: pixels whose light does not change add no noise). An unbiased estimator keeps
// any fixed sum unbiased, and a sum over many pixels and 512 seeds has near-normal noise,
// where single pixels' means over a few seeds have heavy tails: a per-pixel chi-square over
// 32 seeds read 0.61 to 1.48 over seed bases and could not tell a 10 % bias. The lamp
// moves between the frames, so that the light changes by many times the noise. The test
// checks its own power too: the same statistic must reject differences a quarter larger or
// smaller than the true ones (the temporal ones it tells apart at a tenth already).
void expectTemporalDifferencesUnbiased(Scene scene, int64_t frameIndex, uint64_t seedBase) {
  const int w = 8, h = 8, seeds = 512;
  const RenderSettings settings = small(w, h, 8, 4);
  const FrameImage before = pathTraced(scene, settings, 16384, frameIndex),
                   after = pathTraced(scene, settings, 16384, frameIndex + 1);
  GradientSettings tgpt;
  tgpt.temporal = true;
  const size_t pixels = static_cast<size_t>(w * h);
  // Per seed, layer (temporal, mixed x, mixed y), channel and pixel: the difference.
  std::vector<double> values(static_cast<size_t>(seeds) * 9 * pixels);
  const auto at = [&](int seed, size_t l, size_t c, size_t p) -> double& {
    return values[((static_cast<size_t>(seed) * 3 + l) * 3 + c) * pixels + p];
  };
  std::vector<int32_t> target;
  for (int seed = 0; seed < seeds; ++seed) {
    scene.seed = seedBase + static_cast<uint64_t>(seed);
    const GradientFrame frame =
        GradientFrame::fromImage(GradientFrameRenderer(scene, settings, tgpt).render(frameIndex), "tgpt");
    if (seed > 0) {
      ASSERT_EQ(frame.temporalTarget, target) << "the correspondence does not depend on the seed";
    }
    target = frame.temporalTarget;
    for (size_t l = 0; l < 3; ++l)
      for (size_t c = 0; c < 3; ++c)
        for (size_t p = 0; p < pixels; ++p)
          at(seed, l, c, p) = (l == 0 ? frame.temporal : l == 1 ? frame.mixedX : frame.mixedY)[c][p];
  }
  int mixedTerms = 0;
  for (size_t l = 0; l < 3; ++l)
    for (size_t c = 0; c < 3; ++c) {
      const std::string channel = kColorChannels[c];
      const auto &b = before.channel(channel), &a = after.channel(channel);
      const auto &bv = before.channel("variance." + channel), &av = after.channel("variance." + channel);
      // The pooled sum's expectation and the reference's variance of it; per seed, its value.
      double expected = 0, referenceVariance = 0;
      std::vector<double> pooled(static_cast<size_t>(seeds), 0.0);
      for (size_t p = 0; p < pixels; ++p) {
        if (target[p] < 0) continue;
        const auto q = static_cast<size_t>(target[p]);
        double difference = a[q] - b[p], variance = av[q] + bv[p];
        if (l > 0) {
          // The mixed rows' neighbour: where the correspondence moves p's neighbour rigidly.
          const size_t step = l == 1 ? 1 : static_cast<size_t>(w);
          if ((l == 1 && (p % w + 1 == static_cast<size_t>(w) || q % w + 1 == static_cast<size_t>(w))) ||
              p + step >= pixels || target[p + step] != static_cast<int32_t>(q + step))
            continue;
          difference = (a[q + step] - a[q]) - (b[p + step] - b[p]);
          variance = av[q + step] + av[q] + bv[p + step] + bv[p];
          mixedTerms += c == 0;
        }
        const double weight = difference;
        expected += weight * difference;
        referenceVariance += weight * weight * variance;
        for (int seed = 0; seed < seeds; ++seed) pooled[static_cast<size_t>(seed)] += weight * at(seed, l, c, p);
      }
      double sum = 0, squares = 0;
      for (double v : pooled) {
        sum += v;
        squares += v * v;
      }
      const auto [mean, variance] = overSeeds(sum, squares, seeds);
      const double sigma = std::sqrt(variance + referenceVariance);
      const std::string what = std::string(l == 0 ? "temporal" : l == 1 ? "mixed x" : "mixed y") + ", " + channel;
      EXPECT_LT(std::abs(mean - expected), 4 * sigma) << what << ": " << mean << " against " << expected;
      for (double scale : {0.75, 1.25})
        EXPECT_GT(std::abs(mean - scale * expected), 4 * sigma)
            << what << ": the statistic cannot tell differences scaled by " << scale;
    }
  ASSERT_GT(mixedTerms, 30);
}

TEST(GradientRender, TemporalAndMixedDifferencesAreUnbiased) {
  expectTemporalDifferencesUnbiased(cornellForStatistics(true), 6, 3000);
}

// The same on a deforming surface: the skinned arm of gltf_arm.h turning its elbow by 22.5
// degrees a frame in front of a dark wall (the arm's contrast against it is what lets the
// statistic tell a quarter's bias in the mixed rows). The temporal offsets replay their
// samples on the next frame's pose.
TEST(GradientRender, TemporalAndMixedDifferencesOnADeformingMeshAreUnbiased) {
  const std::filesystem::path folder = test_support::processTemporaryFolder("pathfarm_tgpt_arm");
  gltftest::GltfBuilder arm = gltftest::skinnedArm({0, 0, 1});
  arm.write(folder, "arm");
  const Scene scene = parseScene(R"({"include": "arm.gltf", "fps": 4, "environment": {"radiance": 0.1},
    "materials": {"wall": {"type": "diffuse", "reflectance": 0.15}, "lamp": {"type": "diffuse", "reflectance": 0}},
    "shapes": [
      {"type": "rectangle", "size": [6, 6], "material": "wall", "transform": {"translate": [1, 0.5, -0.6]}},
      {"type": "rectangle", "size": [1, 1], "material": "lamp", "emission": 8,
       "transform": {"translate": [1, 2.5, 1], "rotate": {"axis": [1, 0, 0], "angle": 90}}}]})",
                                 folder / "arm.json");
  ASSERT_TRUE(scene.objects[0].deformation);
  expectTemporalDifferencesUnbiased(scene, 1, 7000);
}

// A floor, a wall, a glass sphere and a lamp, nothing moving.
const char* const kStillBox = R"({
  "camera": {"position": [0, 1, 3], "look_at": [0, 0.5, 0], "fov": 50},
  "materials": {"white": {"type": "diffuse", "reflectance": 0.7}, "glass": {"type": "dielectric"}},
  "shapes": [
    {"type": "rectangle", "size": [4, 4], "material": "white", "transform": {"rotate": {"axis": [1, 0, 0], "angle": -90}}},
    {"type": "rectangle", "size": [4, 4], "material": "white", "transform": {"translate": [0, 2, -1]}},
    {"type": "sphere", "radius": 0.4, "material": "glass", "transform": {"translate": [0, 0.4, 0]}},
    {"type": "rectangle", "size": [1, 1], "material": "white", "emission": 5,
     "transform": {"translate": [0, 2.5, 0], "rotate": {"axis": [1, 0, 0], "angle": 90}}}]})";

// Every pixel's horizontal and vertical difference, averaged over many seeds, against the
// differences of a converged path-traced image: the squared deviations in units of their
// standard error must average about 1. The image is tiny so that neighbouring pixels see
// points far apart, where the reconnection's Jacobian is far from 1.
TEST(GradientRender, DifferencesAreUnbiased) {
  Scene scene = cornellForStatistics();
  const int w = 8, h = 8, seeds = 48;
  const RenderSettings settings = small(w, h, 16, 5);
  const FrameImage truth = pathTraced(scene, settings, 65536, 3);
  const size_t pixels = static_cast<size_t>(w * h);
  std::vector<double> sum(6 * pixels, 0.0), squares(6 * pixels, 0.0);
  for (int seed = 0; seed < seeds; ++seed) {
    scene.seed = 2000 + static_cast<uint64_t>(seed);
    const FrameImage image = GradientFrameRenderer(scene, settings, {}).render(3);
    for (size_t c = 0; c < 3; ++c)
      for (size_t axis = 0; axis < 2; ++axis) {
        const auto& g = image.channel((axis ? "gradient_y." : "gradient_x.") + std::string(kColorChannels[c]));
        for (size_t p = 0; p < pixels; ++p) {
          sum[(2 * c + axis) * pixels + p] += g[p];
          squares[(2 * c + axis) * pixels + p] += static_cast<double>(g[p]) * g[p];
        }
      }
  }
  double chiSquare = 0;
  int terms = 0;
  for (size_t c = 0; c < 3; ++c) {
    const auto& ref = truth.channel(kColorChannels[c]);
    const auto& refVariance = truth.channel(std::string("variance.") + kColorChannels[c]);
    for (size_t axis = 0; axis < 2; ++axis)
      for (int y = 0; y < h - static_cast<int>(axis); ++y)
        for (int x = 0; x < w - static_cast<int>(1 - axis); ++x) {
          const size_t p = static_cast<size_t>(y * w + x), q = axis ? p + w : p + 1;
          const size_t i = (2 * c + axis) * pixels + p;
          const auto [mean, variance] = overSeeds(sum[i], squares[i], seeds);
          const double expected = ref[q] - ref[p];
          const double total = variance + refVariance[p] + refVariance[q];
          if (total == 0) {  // both black: nothing to compare but the values
            EXPECT_EQ(mean, expected);
            continue;
          }
          chiSquare += (mean - expected) * (mean - expected) / total;
          ++terms;
        }
  }
  EXPECT_LT(chiSquare / terms, 1.3);
  EXPECT_GT(chiSquare / terms, 0.7);
}

TEST(GradientRender, TemporalOffsetsOfAStillSceneReplayTheirBaseSamples) {
  const Scene scene = test_support::sceneFromJson(kStillBox);
  GradientSettings tgpt;
  tgpt.temporal = true;
  const FrameImage image = GradientFrameRenderer(scene, small(10, 8, 2, 4), tgpt).render(2);
  for (float v : image.channel("temporal.valid.Y")) ASSERT_EQ(v, 1.0f);
  for (const char* c : {"R", "G", "B"})
    for (const std::string layer : {"temporal.", "mixed_x.", "mixed_y."})
      for (float t : image.channel(layer + c)) ASSERT_EQ(t, 0.0f) << layer << c;
  const auto& tx = image.channel("temporal.target.X");
  for (size_t p = 0; p < tx.size(); ++p) EXPECT_EQ(tx[p], static_cast<float>(p % 10));
}

TEST(GradientRender, ThreadsTilesAndBatchesGiveIdenticalBits) {
  const Scene scene = loadScene(test_support::sourceDir() / "scenes/cornell/scene.json");
  GradientSettings tgpt;
  tgpt.temporal = true;
  tgpt.batches = 2;
  std::vector<FrameImage> images;
  for (const auto& [threads, tile] : {std::pair{1, 5}, std::pair{2, 16}}) {
    RenderSettings settings = small(20, 14, 4, 4);
    settings.threads = threads;
    settings.tileSize = tile;
    images.push_back(GradientFrameRenderer(scene, settings, tgpt).render(7));
  }
  ASSERT_TRUE(images[0].hasChannel("temporal.R"));
  for (const std::string& name : images[0].channelNames())
    EXPECT_EQ(images[0].channel(name), images[1].channel(name)) << name;
  // Adaptive batches spend about the same samples, unevenly.
  const auto& counts = images[0].channel("sample_count.Y");
  double total = 0;
  for (float n : counts) total += n;
  EXPECT_NEAR(total, 4.0 * 20 * 14, 20 * 14 * 0.05);
  EXPECT_GT(*std::max_element(counts.begin(), counts.end()), *std::min_element(counts.begin(), counts.end()));
}

TEST(GradientRender, MixedOffsetsOnFewerSamplesLeaveEveryOtherLayerAlone) {
  // The temporal offset replays the base's random numbers whether or not it traces its
  // spatial offsets, so only the mixed layers (and the timing) may change.
  const Scene scene = loadScene(test_support::sourceDir() / "scenes/cornell/scene.json");
  GradientSettings every, fewer;
  every.temporal = fewer.temporal = true;
  every.mixedEvery = 1;
  fewer.mixedEvery = 3;
  const RenderSettings settings = small(12, 10, 3 * kMinMixedSamples, 4);
  const FrameImage a = GradientFrameRenderer(scene, settings, every).render(7);
  const FrameImage b = GradientFrameRenderer(scene, settings, fewer).render(7);
  size_t mixedDiffer = 0;
  for (const std::string& name : a.channelNames()) {
    if (name.starts_with("mixed_")) {
      mixedDiffer += a.channel(name) != b.channel(name);
      for (float v : b.channel(name)) ASSERT_TRUE(std::isfinite(v)) << name;  // every pixel has sample 0
    } else {
      EXPECT_EQ(a.channel(name), b.channel(name)) << name;
    }
  }
  EXPECT_GT(mixedDiffer, 0u);
  EXPECT_THROW(GradientFrameRenderer(scene, settings, GradientSettings{.temporal = true, .mixedEvery = 0}),
               std::invalid_argument);
}

TEST(GradientRender, MixedOffsetsOnFewerSamplesStopShortOfLeavingAPixelTooFew) {
  // At 12 spp, one sample in 4 would leave 3 with mixed offsets: N falls to 1, and every
  // sample traces them.
  const Scene scene = loadScene(test_support::sourceDir() / "scenes/cornell/scene.json");
  const GradientSettings defaults{.temporal = true};
  ASSERT_GT(defaults.mixedEvery, 1);
  for (const int spp : {12, 2 * defaults.mixedEvery * kMinMixedSamples}) {
    const FrameImage estimates = GradientFrameRenderer(scene, small(6, 4, spp, 4), defaults).renderWindow(7, {0, 0, 6, 4});
    const float expected = spp < defaults.mixedEvery * kMinMixedSamples ? spp : spp / defaults.mixedEvery;
    for (float n : estimates.channel("mixed_samples.Y")) EXPECT_EQ(n, expected) << spp << " spp";
  }
}

}  // namespace
}  // namespace pathfarm

namespace pathfarm {
namespace {

TEST(GradientRender, WindowsRenderedApartAndJoinedAreTheWholeFrameBitForBit) {
  // A moving scene, so pairs across window borders have temporal and mixed differences;
  // windows of uneven sizes, each rendered by its own renderer (another worker).
  const Scene scene = loadScene(test_support::sourceDir() / "scenes/cornell/scene.json");
  GradientSettings tgpt;
  tgpt.temporal = true;
  const RenderSettings settings = small(21, 13, 3, 4);
  const FrameImage whole = GradientFrameRenderer(scene, settings, tgpt).render(7);
  const std::vector<PixelWindow> windows = {{0, 0, 8, 5}, {8, 0, 21, 5}, {0, 5, 21, 6}, {0, 6, 13, 13}, {13, 6, 21, 13}};
  std::vector<FrameImage> estimates;
  for (const PixelWindow& window : windows)
    estimates.push_back(GradientFrameRenderer(scene, settings, tgpt).renderWindow(7, window));
  std::vector<PlacedEstimates> placed;
  for (size_t i = 0; i < windows.size(); ++i) placed.push_back({&estimates[i], windows[i].x0, windows[i].y0});
  const FrameImage joined = gradientFrameFromEstimates(placed, 21, 13);
  ASSERT_TRUE(whole.hasChannel("mixed_x.R"));
  ASSERT_EQ(joined.channelNames(), whole.channelNames());
  for (const std::string& name : whole.channelNames()) {
    const auto &a = whole.channel(name), &b = joined.channel(name);
    ASSERT_EQ(a.size(), b.size());
    // Bit for bit, NaN (a mixed pair without samples) included.
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0) << name;
  }
  EXPECT_EQ(joined.attributes(), whole.attributes());

  // Windows that leave a pixel out or cover one twice are refused, as is a window of an
  // adaptive render.
  placed.pop_back();
  EXPECT_THROW(gradientFrameFromEstimates(placed, 21, 13), std::invalid_argument);
  placed.push_back({&estimates[0], 13, 6});
  EXPECT_THROW(gradientFrameFromEstimates(placed, 21, 13), std::invalid_argument);
  GradientSettings adaptive = tgpt;
  adaptive.batches = 2;
  EXPECT_THROW(GradientFrameRenderer(scene, settings, adaptive).renderWindow(7, windows[0]), std::invalid_argument);
  EXPECT_THROW(GradientFrameRenderer(scene, settings, tgpt).renderWindow(7, {0, 0, 22, 13}), std::invalid_argument);
}

}  // namespace
}  // namespace pathfarm
