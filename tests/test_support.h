#pragma once
// Shared by the tests: scenes from inline JSON, and statistics over rendered pixels.
#include <cmath>
#include <filesystem>
#include <random>
#include <set>
#include <system_error>
#include <string>
#include <utility>

#include <unistd.h>

#include <gtest/gtest.h>

#include "image/frame_image.h"
#include "renderer/integrators/frame_renderer.h"
#include "renderer/scene/scene_loader.h"

namespace pathfarm::test_support {

inline std::filesystem::path sourceDir() { return PATHFARM_SOURCE_DIR; }

// The folders processTemporaryFolder made, removed when the test process ends.
class TemporaryFolders {
 public:
  void add(const std::filesystem::path& folder) { folders_.insert(folder); }
  ~TemporaryFolders() {
    for (const auto& folder : folders_) {
      std::error_code ignored;
      std::filesystem::remove_all(folder, ignored);
    }
  }

 private:
  std::set<std::filesystem::path> folders_;
};

// A folder under the temporary directory that no other test process uses, created, and
// removed with everything in it when the process ends.
// ctest runs every test as a process of its own, two at a time: tests sharing a fixed
// folder rewrite each other's files while they are being read.
inline std::filesystem::path processTemporaryFolder(const std::string& prefix) {
  static TemporaryFolders made;
  const std::filesystem::path folder = std::filesystem::temp_directory_path() / (prefix + "_" + std::to_string(::getpid()));
  std::filesystem::create_directories(folder);
  made.add(folder);
  return folder;
}

// A frame rendered twice, render(settings), on 1 thread in 8-pixel tiles and on 2
// threads in 5-pixel tiles: the determinism tests compare the two frames' bits.
template <class Render>
std::pair<FrameImage, FrameImage> renderedTwoWays(RenderSettings settings, Render render) {
  settings.threads = 1;
  settings.tileSize = 8;
  FrameImage first = render(settings);
  settings.threads = 2;
  settings.tileSize = 5;
  return {std::move(first), render(settings)};
}

// A scene parsed from text as if it were `folder/scene.json`.
inline Scene sceneFromJson(const std::string& json,
                           const std::filesystem::path& folder = std::filesystem::temp_directory_path()) {
  return parseScene(json, folder / "scene.json");
}

// The message of the SceneError that load() throws, or "(no error)".
template <class Load>
std::string sceneErrorOf(Load load) {
  try {
    load();
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no error)";
}

// The mean of one beauty channel over all pixels and its standard error, from the
// per-pixel variances of the mean that the renderer writes.
struct MeanEstimate {
  double mean = 0;
  double standardError = 0;
};

inline MeanEstimate meanOverPixels(const FrameImage& image, const std::string& channel) {
  const auto& values = image.channel(channel);
  const auto& variances = image.channel("variance." + channel);
  double sum = 0, varianceSum = 0;
  for (size_t i = 0; i < values.size(); ++i) {
    sum += values[i];
    varianceSum += variances[i];
  }
  const double n = static_cast<double>(values.size());
  return {sum / n, std::sqrt(varianceSum) / n};
}

// meanOverPixels of a 16 x 16 path-traced frame of `scene`.
inline MeanEstimate renderedMean(const Scene& scene, int spp, int maxDepth, const std::string& channel = "G") {
  RenderSettings settings;
  settings.width = settings.height = 16;
  settings.spp = spp;
  settings.maxDepth = maxDepth;
  return meanOverPixels(FrameRenderer(scene, settings).render(0), channel);
}

// Frame `frame` of a scene of the source tree (e.g. "scenes/cornell/scene.json") with the
// standard decomposition, path depth 6 and motion vectors reaching `span` frames, as a
// worker's render tiles make it.
inline FrameImage renderDecomposed(const std::string& sceneFile, int width, int height, int spp, int64_t frame,
                                   MotionSpan span = {}, int reflectanceSpp = 0) {
  RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.spp = spp;
  settings.reflectanceSpp = reflectanceSpp;
  settings.maxDepth = 6;
  settings.decomposition = std::make_shared<Decomposition>(Decomposition::standard());
  settings.motionSpan = span;
  return FrameRenderer(loadScene(sourceDir() / sceneFile), settings).render(frame);
}

// A deterministic value in [0, 1) per (seed, c, x, y): test images without a generator.
inline float hashed(uint32_t seed, int c, int x, int y) {
  uint32_t h = seed * 0x9E3779B9u ^ static_cast<uint32_t>(c) * 0x85EBCA6Bu ^ static_cast<uint32_t>(x) * 0xC2B2AE35u ^
               static_cast<uint32_t>(y) * 0x27D4EB2Fu;
  h ^= h >> 15;
  h *= 0x2C1B3C6Du;
  h ^= h >> 12;
  h *= 0x297A2D39u;
  h ^= h >> 15;
  return static_cast<float>(h >> 8) / 16777216.0f;
}

inline void expectNear(Vec3f a, Vec3f b, float tolerance = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

// A smooth picture to measure errors against: R, G, B between 0.3 and 0.8.
inline FrameImage smoothTruth(int width, int height) {
  FrameImage truth(width, height);
  const char* names[] = {"R", "G", "B"};
  for (int c = 0; c < 3; ++c) {
    std::vector<float>& values = truth.addChannel(names[c]);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x)
        values[static_cast<size_t>(y) * width + x] =
            static_cast<float>(0.3 + 0.5 * (0.5 + 0.5 * std::sin(x / 7.0 + c)) * (0.5 + 0.5 * std::cos(y / 9.0)));
  }
  return truth;
}

// `truth` with Gaussian noise of standard deviation `sigma` per value (drawn from `seed`),
// and with `withVariance` its exact variance in variance.R/G/B, as an unbiased render of
// the truth carries it.
inline FrameImage noisyCopy(const FrameImage& truth, double sigma, uint64_t seed, bool withVariance) {
  std::mt19937_64 random(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  FrameImage copy(truth.width(), truth.height());
  for (const char* name : {"R", "G", "B"}) {
    const std::vector<float>& values = truth.channel(name);
    std::vector<float>& noisy = copy.addChannel(name);
    for (size_t p = 0; p < values.size(); ++p) noisy[p] = static_cast<float>(values[p] + noise(random));
    if (withVariance) copy.addChannel(std::string("variance.") + name).assign(values.size(), static_cast<float>(sigma * sigma));
  }
  return copy;
}

}  // namespace pathfarm::test_support
