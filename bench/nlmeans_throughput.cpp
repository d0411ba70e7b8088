// Joint NL-means alone, as the denoise task runs it per component: a frame and its two
// warped neighbours, three color channels with their variances, a normal, a reflectance
// and an object id as features, r = 5 and f = 3 (the spatio-temporal defaults).
//
//   build/bin/nlmeans_throughput [--res 320x180] [--frames 3] [--radius 5] [--repeat 5] [--threads 1]
//                                [--baseline]
//
// The input is synthetic and fixed (a seeded generator): noisy shading over flat-shaded
// tiles, so that the feature weights cut where real frames' edges do. Prints the median
// seconds per call, the nanoseconds per pixel and search offset, and a digest of the
// output's bits: two builds that agree on it filter identically. --baseline filters without
// AVX2 (NlMeansSettings::wideVectors), which must print the same digest.
#include <tbb/global_control.h>

#include <bit>
#include <cstdio>
#include <random>
#include <string>

#include "bench/bench_support.h"
#include "bench/command_line.h"
#include "bench/median.h"
#include "postproc/filters/nlmeans.h"

namespace {

using namespace pathfarm;

// A frame of flat tiles (16 pixels on a side) with noisy shading; the neighbours differ
// by their noise and by a few tiles of another object.
NlMeansFrame syntheticFrame(int width, int height, uint32_t seed, bool neighbour) {
  std::mt19937 random(seed);
  std::normal_distribution<float> noise(0.0f, 0.2f);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  NlMeansFrame frame;
  frame.color = Planes(width, height, 3);
  frame.variance = Planes(width, height, 3);
  frame.features = {Planes(width, height, 3), Planes(width, height, 3), Planes(width, height, 1)};
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const size_t p = static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x);
      const int tile = (x / 16) * 7 + (y / 16) * 13;
      const float shade = 0.2f + 0.1f * static_cast<float>(tile % 7);
      for (int c = 0; c < 3; ++c) {
        const float value = shade * (1.0f + noise(random));
        frame.color.channels[static_cast<size_t>(c)][p] = value < 0.0f ? 0.0f : value;
        frame.variance.channels[static_cast<size_t>(c)][p] = 0.04f * shade * shade * (0.5f + unit(random));
        frame.features[0].channels[static_cast<size_t>(c)][p] = c == 2 ? 1.0f : 0.1f * static_cast<float>(tile % 3);
        frame.features[1].channels[static_cast<size_t>(c)][p] = 0.3f + 0.05f * static_cast<float>((tile + c) % 5);
      }
      frame.features[2].channels[0][p] = static_cast<float>((tile % 11 == 0 && neighbour) ? 99 : tile % 4);
    }
  }
  return frame;
}

uint64_t digest(const Planes& planes) {
  uint64_t hash = 1469598103934665603ull;
  for (const std::vector<float>& channel : planes.channels)
    for (float value : channel) hash = (hash ^ std::bit_cast<uint32_t>(value)) * 1099511628211ull;
  return hash;
}

}  // namespace

int main(int argc, char** argv) {
  bench::CommandLine app("joint NL-means throughput");
  std::string resolution = "320x180";
  int frames = 3, radius = 5, repeat = 5, threads = 1;
  app.option("--res", resolution);
  app.option("--frames", frames).range(1, 8);
  app.option("--radius", radius).range(0, 16);
  app.option("--repeat", repeat).range(1, 1000);
  app.option("--threads", threads).range(1, 256);
  bool baseline = false;
  app.flag("--baseline", baseline, "without AVX2 vectors");
  if (const auto exit = app.parse(argc, argv)) return *exit;
  int width = 0, height = 0;
  if (std::sscanf(resolution.c_str(), "%dx%d", &width, &height) != 2 || width <= 0 || height <= 0) {
    std::fprintf(stderr, "--res: expected WIDTHxHEIGHT, got %s\n", resolution.c_str());
    return 2;
  }
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));

  NlMeansInput input;
  input.featureKinds = {FeatureKind::Continuous, FeatureKind::Continuous, FeatureKind::ExactMatch};
  for (int t = 0; t < frames; ++t) input.frames.push_back(syntheticFrame(width, height, 7u + t, t > 0));
  NlMeansSettings settings;
  settings.radius = radius;
  settings.wideVectors = !baseline;

  Planes out;
  std::vector<double> times;
  for (int i = 0; i < repeat; ++i) times.push_back(bench::seconds([&] { out = jointNlMeans(input, settings); }));
  const double perCall = bench::median(times);
  const double offsets = static_cast<double>(frames) * (2 * radius + 1) * (2 * radius + 1);
  std::printf("%dx%d, %d frames, r=%d, f=%d, %d thread(s)%s: %.4f s per call (median of %d), %.2f ns per pixel and offset\n",
              width, height, frames, radius, settings.patch, threads, baseline ? ", baseline" : "", perCall, repeat,
              1e9 * perCall / (static_cast<double>(width) * height * offsets));
  std::printf("output digest %016llx\n", static_cast<unsigned long long>(digest(out)));
  return 0;
}
