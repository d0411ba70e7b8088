// Path tracer throughput against the limit Embree alone sets on the same scene.
//
//   build/bin/render_throughput [--scene scenes/cornell/scene.json] [--res 256x256]
//                               [--spp 16] [--max-depth 13] [--frame 0] [--repeat 5]
//                               [--decompose default]
//
// Prints, as medians over the repeats: samples per second and rays per second of the
// path tracer, the closest-hit rays per second Embree reaches tracing as many random
// rays (origins inside the scene's bounds, uniform directions) against the same frame's
// geometry, and the ratio of the two ray rates. With --decompose, also the time of a
// decomposed render against the plain one at equal spp, interleaved run by run.
#include <embree3/rtcore.h>
#include <tbb/parallel_for.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

#include "bench/median.h"
#include "renderer/accel/frame_geometry.h"
#include "renderer/decomposition/auto_decomposition.h"
#include "renderer/integrators/frame_renderer.h"
#include "renderer/math/sampling.h"
#include "renderer/scene/scene_loader.h"

namespace {

using namespace pathfarm;
using bench::median;

// Traces `count` random rays with rtcIntersect1 in parallel; returns rays per second.
double embreeRaysPerSecond(const FrameGeometry& geometry, uint64_t count) {
  const Bounds3 b = geometry.bounds();
  const auto start = std::chrono::steady_clock::now();
  tbb::parallel_for(tbb::blocked_range<uint64_t>(0, count, 4096), [&](const tbb::blocked_range<uint64_t>& r) {
    SampleStream stream({7, 0, static_cast<int32_t>(r.begin() >> 12), 0, 0});
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (uint64_t i = r.begin(); i != r.end(); ++i) {
      const Vec3f u{stream.next1D(), stream.next1D(), stream.next1D()};
      const Vec3f d = sampleUniformSphere(stream.next2D());
      RTCRayHit rh{};
      rh.ray.org_x = b.lower.x + u.x * (b.upper.x - b.lower.x);
      rh.ray.org_y = b.lower.y + u.y * (b.upper.y - b.lower.y);
      rh.ray.org_z = b.lower.z + u.z * (b.upper.z - b.lower.z);
      rh.ray.dir_x = d.x;
      rh.ray.dir_y = d.y;
      rh.ray.dir_z = d.z;
      rh.ray.tfar = 1e30f;
      rh.ray.time = stream.next1D();
      rh.ray.mask = 0xffffffffu;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(geometry.embreeScene(), &context, &rh);
    }
  });
  return static_cast<double>(count) / std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"pathfarm render throughput benchmark"};
  std::string scenePath = "scenes/cornell/scene.json", resolution = "256x256";
  int spp = 16, maxDepth = 13, frame = 0, repeat = 5;
  std::string decompose;
  app.add_option("--scene", scenePath);
  app.add_option("--res", resolution);
  app.add_option("--spp", spp);
  app.add_option("--max-depth", maxDepth, "13 scattering events = 12 bounces after direct light, as Cycles counts");
  app.add_option("--frame", frame);
  app.add_option("--repeat", repeat);
  app.add_option("--decompose", decompose, "also measure this decomposition's overhead (e.g. default, auto)");
  CLI11_PARSE(app, argc, argv);

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
    const FrameRenderer decomposingRenderer(scene, decomposed);
    std::vector<double> plainSeconds, decomposedSeconds;
    for (int i = 0; i < repeat; ++i) {
      RenderStats stats;
      renderer.render(frame, {}, &stats);
      plainSeconds.push_back(stats.seconds);
      decomposingRenderer.render(frame, {}, &stats);
      decomposedSeconds.push_back(stats.seconds);
    }
    const double plain = median(plainSeconds), split = median(decomposedSeconds);
    std::printf("decomposition %s: %.3f s against %.3f s plain, overhead %.1f %%\n",
                decomposed.decomposition ? decomposed.decomposition->describe().c_str() : "none", split, plain,
                100 * (split / plain - 1));
  }
  return 0;
}
