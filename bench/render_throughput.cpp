// Path tracer throughput against the limit Embree alone sets on the same scene.
//
//   build/bin/render_throughput [--scene scenes/cornell/scene.json] [--res 256x256]
//                               [--spp 16] [--max-depth 13] [--frame 0] [--repeat 5]
//                               [--decompose default] [--reflectance-spp 16]
//
// Prints, as medians over the repeats: samples per second and rays per second of the
// path tracer, the closest-hit rays per second Embree reaches tracing as many random
// rays (origins inside the scene's bounds, uniform directions) against the same frame's
// geometry, and the ratio of the two ray rates. With --decompose, also the time of a
// decomposed render against the plain one at equal spp, interleaved run by run, with the
// lowest and highest ratio of a plain render and the decomposed one run right after it,
// and the decomposed render without measuring motion (what features and re-render tiles
// of a filtering pipeline do) against it. With --reflectance-spp as well, that render with
// that many samples of reflectance (an in-between frame's feature render) against it.
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "bench/command_line.h"
#include "bench/embree_rays.h"
#include "bench/median.h"
#include "image/plane_memory.h"
#include "renderer/accel/frame_geometry.h"
#include "renderer/setup/auto_decomposition.h"
#include "renderer/integrators/frame_renderer.h"
#include "renderer/scene/scene_loader.h"

namespace {

using namespace pathfarm;
using bench::embreeRaysPerSecond;
using bench::median;

double secondsOf(const FrameRenderer& renderer, int frame) {
  RenderStats stats;
  renderer.render(frame, {}, &stats);
  return stats.seconds;
}

// A variant's render times, each with the time of the render it is compared with, run
// right before it: the ratios of the pairs show how far the machine's noise reaches.
struct PairedTimes {
  std::vector<double> seconds, against, ratios;
  void add(double variant, double baseline) {
    seconds.push_back(variant);
    against.push_back(baseline);
    ratios.push_back(variant / baseline);
  }
  double median() const { return bench::median(seconds); }
  std::string ratioRange() const {
    char text[64];
    std::snprintf(text, sizeof text, "%.3f to %.3f", *std::min_element(ratios.begin(), ratios.end()),
                  *std::max_element(ratios.begin(), ratios.end()));
    return text;
  }
};

}  // namespace

int main(int argc, char** argv) {
  bench::CommandLine app("pathfarm render throughput benchmark");
  std::string scenePath = "scenes/cornell/scene.json", resolution = "256x256";
  int spp = 16, maxDepth = 13, frame = 0, repeat = 5, reflectanceSpp = 0;
  std::string decompose;
  app.option("--scene", scenePath);
  app.option("--res", resolution);
  app.option("--spp", spp);
  app.option("--max-depth", maxDepth, "13 scattering events = 12 bounces after direct light, as Cycles counts");
  app.option("--frame", frame);
  app.option("--repeat", repeat);
  app.option("--decompose", decompose, "also measure this decomposition's overhead (e.g. default, auto)");
  app.option("--reflectance-spp", reflectanceSpp, "with --decompose, also measure this many samples of reflectance");
  if (const auto exit = app.parse(argc, argv)) return *exit;
  keepFreedPlanesForReuse();  // as pathfarm's processes do: a render's planes reuse freed pages

  const Scene scene = loadScene(scenePath);
  RenderSettings settings = RenderSettings::defaultsOf(scene);
  if (std::sscanf(resolution.c_str(), "%dx%d", &settings.width, &settings.height) != 2) return 2;
  settings.spp = spp;
  settings.maxDepth = maxDepth;
  const FrameRenderer renderer(scene, settings);

  std::vector<double> samplesPerSecond, raysPerSecond, embreePerSecond;
  EmbreeDevice device;
  const ShotGeometry shot(scene, device);
  const FrameGeometry geometry(shot, frame);
  for (int i = 0; i < repeat; ++i) {
    RenderStats stats;
    renderer.render(frame, {}, &stats);
    const uint64_t rays = stats.rays.closestHit + stats.rays.shadow;
    samplesPerSecond.push_back(static_cast<double>(stats.samples) / stats.seconds);
    raysPerSecond.push_back(static_cast<double>(rays) / stats.seconds);
    embreePerSecond.push_back(embreeRaysPerSecond(geometry, rays));
  }
  const double sps = median(samplesPerSecond), rps = median(raysPerSecond), eps = median(embreePerSecond);
  std::printf("scene %s, frame %d, %dx%d, %d spp, max depth %d, %d repeats (medians)\n", scenePath.c_str(), frame,
              settings.width, settings.height, spp, maxDepth, repeat);
  std::printf("path tracer:  %.3f M samples/s, %.2f M rays/s\n", sps * 1e-6, rps * 1e-6);
  std::printf("embree alone: %.2f M rays/s (random rays, same geometry)\n", eps * 1e-6);
  std::printf("ratio path tracer / embree rays: %.2f\n", rps / eps);

  if (!decompose.empty()) {
    RenderSettings decomposed = settings;
    decomposed.decomposition = decompositionFor(scene, decompose);
    RenderSettings motionless = decomposed;
    motionless.motion = false;
    RenderSettings reflective = motionless;
    reflective.reflectanceSpp = reflectanceSpp;
    const FrameRenderer decomposingRenderer(scene, decomposed), motionlessRenderer(scene, motionless),
        reflectiveRenderer(scene, reflective);
    PairedTimes split, withoutMotion, withReflectance;
    for (int i = 0; i < repeat; ++i) {
      const double plainSeconds = secondsOf(renderer, frame);
      const double splitSeconds = secondsOf(decomposingRenderer, frame);
      split.add(splitSeconds, plainSeconds);  // each pair runs back to back
      const double motionlessSeconds = secondsOf(motionlessRenderer, frame);
      withoutMotion.add(motionlessSeconds, splitSeconds);
      if (reflectanceSpp > spp) withReflectance.add(secondsOf(reflectiveRenderer, frame), motionlessSeconds);
    }
    std::printf("decomposition %s: %.3f s against %.3f s plain, overhead %.1f %% (pairs: %s)\n",
                decomposed.decomposition ? decomposed.decomposition->describe().c_str() : "none", split.median(),
                median(split.against), 100 * (split.median() / median(split.against) - 1), split.ratioRange().c_str());
    std::printf("without motion: %.3f s, %.3f of the decomposed render (pairs: %s)\n", withoutMotion.median(),
                withoutMotion.median() / split.median(), withoutMotion.ratioRange().c_str());
    if (!withReflectance.seconds.empty())
      std::printf("with %d samples of reflectance: %.3f s, %.3f of the render without motion (pairs: %s)\n",
                  reflectanceSpp, withReflectance.median(), withReflectance.median() / withoutMotion.median(),
                  withReflectance.ratioRange().c_str());
  }
  return 0;
}
