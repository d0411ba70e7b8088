// What a large scene costs: import time, peak memory, the per-frame cost of placing
// objects and posing deforming meshes, and render speed against the limit Embree alone
// sets on the same geometry.
//
//   build/bin/scene_scale --scene FILE [--res 320x180] [--spp 4] [--frame 0] [--repeat 3]
//
// FILE is any scene pathfarm renders (a glTF file, or a JSON scene including one).
// Prints the triangles placed in the scene and those stored (a mesh placed many times is
// stored once), the import time (parsing and decoding the file into a Scene), the time to
// build the ray-tracing geometry and light sampler, the process's peak resident memory
// after each, and, as medians over the repeats, the time to build one frame's geometry
// (FrameGeometry: placements, and the poses and BVH of deforming meshes, paid by every
// frame a worker renders) beside the frame's render time and its share of it,
// path-tracer samples/s and rays/s, and the closest-hit rays/s Embree alone reaches with
// random rays on the same frame geometry.
#include <sys/resource.h>

#include <cstdio>
#include <memory>
#include <set>
#include <vector>

#include "bench/command_line.h"
#include "bench/bench_support.h"
#include "bench/embree_rays.h"
#include "bench/median.h"
#include "renderer/scene/scene_loader.h"

namespace {

using namespace pathfarm;

double peakResidentMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024;  // kilobytes on Linux
}

}  // namespace

int main(int argc, char** argv) {
  bench::CommandLine app("pathfarm scene scale benchmark");
  std::string scenePath, resolution = "320x180";
  int spp = 4, frame = 0, repeat = 3;
  app.option("--scene", scenePath).required();
  app.option("--res", resolution);
  app.option("--spp", spp);
  app.option("--frame", frame);
  app.option("--repeat", repeat);
  if (const auto exit = app.parse(argc, argv)) return *exit;

  const double startMiB = peakResidentMiB();
  std::unique_ptr<Scene> scene;
  const double importSeconds = bench::seconds([&] { scene = std::make_unique<Scene>(loadScene(scenePath)); });
  const double importMiB = peakResidentMiB();
  size_t placed = 0, stored = 0;
  std::set<const TriangleMesh*> meshes;
  for (const SceneObject& object : scene->objects) {
    if (!object.mesh) continue;
    placed += object.mesh->triangleCount();
    if (meshes.insert(object.mesh.get()).second) stored += object.mesh->triangleCount();
  }

  RenderSettings settings = RenderSettings::defaultsOf(*scene);
  if (std::sscanf(resolution.c_str(), "%dx%d", &settings.width, &settings.height) != 2) return 2;
  settings.spp = spp;
  std::unique_ptr<FrameRenderer> renderer;
  const double buildSeconds =
      bench::seconds([&] { renderer = std::make_unique<FrameRenderer>(*scene, settings); });
  const double buildMiB = peakResidentMiB();

  std::vector<double> samplesPerSecond, raysPerSecond, embreePerSecond, renderSeconds;
  std::vector<uint64_t> rayCounts;
  for (int i = 0; i < repeat; ++i) {
    RenderStats stats;
    renderSeconds.push_back(bench::seconds([&] { renderer->render(frame, {}, &stats); }));
    rayCounts.push_back(stats.rays.closestHit + stats.rays.shadow);
    samplesPerSecond.push_back(static_cast<double>(stats.samples) / stats.seconds);
    raysPerSecond.push_back(static_cast<double>(rayCounts.back()) / stats.seconds);
  }
  const double renderMiB = peakResidentMiB();
  std::vector<double> frameGeometrySeconds;
  {
    // A second copy of the geometry for Embree alone, after the memory figures are taken.
    const EmbreeDevice device;
    const ShotGeometry shot(*scene, device);
    for (int i = 0; i < repeat; ++i)
      frameGeometrySeconds.push_back(bench::seconds([&] { const FrameGeometry placed(shot, frame); }));
    const FrameGeometry geometry(shot, frame);
    for (int i = 0; i < repeat; ++i) embreePerSecond.push_back(bench::embreeRaysPerSecond(geometry, rayCounts[i]));
  }

  const double sps = bench::median(samplesPerSecond), rps = bench::median(raysPerSecond),
               eps = bench::median(embreePerSecond);
  std::printf("scene %s: %zu objects, %.3f M triangles placed, %.3f M stored\n", scenePath.c_str(),
              scene->objects.size(), placed * 1e-6, stored * 1e-6);
  std::printf("import:   %.2f s, peak resident %.0f MiB (%.0f MiB before)\n", importSeconds, importMiB, startMiB);
  std::printf("geometry: %.2f s (BVH and light sampler), peak resident %.0f MiB\n", buildSeconds, buildMiB);
  std::printf("render:   frame %d, %dx%d, %d spp, %d repeats (medians); peak resident %.0f MiB\n", frame,
              settings.width, settings.height, spp, repeat, renderMiB);
  const double perFrame = bench::median(frameGeometrySeconds), render = bench::median(renderSeconds);
  std::printf("per frame: geometry %.4f s (placements, deforming meshes posed and their BVH) of the render's %.3f s: "
              "%.2f %%\n",
              perFrame, render, 100 * perFrame / render);
  std::printf("path tracer:  %.3f M samples/s, %.2f M rays/s\n", sps * 1e-6, rps * 1e-6);
  std::printf("embree alone: %.2f M rays/s (random rays, same geometry)\n", eps * 1e-6);
  std::printf("ratio path tracer / embree rays: %.2f\n", rps / eps);
  return 0;
}
