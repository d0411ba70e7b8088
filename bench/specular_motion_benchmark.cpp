// Specular motion by temporal manifold exploration (issue 4): how many specular pixels
// are tracked, how many iterations a walk takes (Zimmer et al. 2015 report 3.72 spatial
// and 1.37 temporal ones), and how long a frame takes.
//
//   build/bin/specular_motion_benchmark [--scene scenes/cornell/scene.json ...]
//                                       [--res 1280x720] [--frame 6] [--repeat 3]
//
// For every scene: the motion of every specular component of the default decomposition
// at every pixel of one frame, as the decomposed film computes it. Prints the share of
// specular pixels (some specular component has a representative path there) that are
// tracked (every such component's walks succeeded both ways), the share of (pixel,
// component) paths needing no walk (nothing on the chain moves), the mean inner (manifold
// steps, one re-trace each, counting the check that the unmoved path still lands) and
// outer (time steps) iterations per walk, one walk being one direction of one path, and
// the share of the paths that were not tracked and their share of the inner iterations
// (a failing walk runs to its bounds), and the median wall seconds per frame over the
// repeats with the processor seconds they took (all threads; steadier than wall time on
// a shared machine).
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <vector>

#include "bench/command_line.h"
#include "bench/bench_support.h"
#include "bench/median.h"
#include "renderer/accel/shot_geometry.h"
#include "renderer/decomposition/specular_motion.h"
#include "renderer/scene/scene_loader.h"

namespace {

using namespace pathfarm;
using bench::median;

struct Tally {
  int64_t specularPixels = 0, trackedPixels = 0, paths = 0, unwalked = 0, walks = 0, inner = 0, outer = 0;
  int64_t untrackedPaths = 0, untrackedInner = 0;  // paths where a walk failed

  Tally& operator+=(const Tally& o) {
    specularPixels += o.specularPixels;
    trackedPixels += o.trackedPixels;
    paths += o.paths;
    unwalked += o.unwalked;
    walks += o.walks;
    inner += o.inner;
    outer += o.outer;
    untrackedPaths += o.untrackedPaths;
    untrackedInner += o.untrackedInner;
    return *this;
  }
};

Tally trackFrame(const SpecularMotion& motion, int components, int width, int height) {
  tbb::enumerable_thread_specific<Tally> tallies;
  tbb::parallel_for(0, height, [&](int y) {
    Tally& t = tallies.local();
    for (int x = 0; x < width; ++x) {
      bool specular = false, tracked = true;
      for (int k = 0; k < components; ++k) {
        if (!motion.isSpecular(k)) continue;
        const SpecularTrack track = motion.track(x, y, k);
        if (!track.hasChain) continue;
        specular = true;
        tracked &= track.tracked();
        ++t.paths;
        t.unwalked += !track.walked;
        t.walks += track.walked ? 2 : 0;
        t.inner += track.counts.inner;
        t.outer += track.counts.outer;
        if (!track.tracked()) {
          ++t.untrackedPaths;
          t.untrackedInner += track.counts.inner;
        }
      }
      t.specularPixels += specular;
      t.trackedPixels += specular && tracked;
    }
  });
  Tally total;
  for (const Tally& t : tallies) total += t;
  return total;
}

}  // namespace

int main(int argc, char** argv) {
  bench::CommandLine app("pathfarm specular motion benchmark");
  std::vector<std::string> scenes{"scenes/cornell/scene.json", "scenes/materials/scene.json"};
  std::string resolution = "1280x720";
  int frame = 6, repeat = 3;
  app.option("--scene", scenes);
  app.option("--res", resolution);
  app.option("--frame", frame);
  app.option("--repeat", repeat).positive();
  if (const auto exit = app.parse(argc, argv)) return *exit;
  int width = 0, height = 0;
  if (std::sscanf(resolution.c_str(), "%dx%d", &width, &height) != 2 || width <= 0 || height <= 0) {
    std::fprintf(stderr, "--res must be WIDTHxHEIGHT\n");
    return 2;
  }

  const Decomposition decomposition = Decomposition::standard();
  for (const std::string& path : scenes) {
    const Scene scene = loadScene(path);
    EmbreeDevice device;
    const ShotGeometry shot(scene, device);
    const FrameGeometry geometry(shot, frame);
    const std::vector<PreciseShape> shapes = preciseShapesOf(scene);
    const SpecularMotion motion(geometry, shapes, decomposition, width, height);
    Tally tally;
    std::vector<double> times, processorTimes;
    for (int i = 0; i < repeat; ++i) {
      const std::clock_t start = std::clock();
      times.push_back(bench::seconds([&] { tally = trackFrame(motion, decomposition.size(), width, height); }));
      processorTimes.push_back(static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC);
    }
    const auto share = [](int64_t part, int64_t whole) { return whole > 0 ? 100.0 * part / whole : 0.0; };
    const auto mean = [](int64_t sum, int64_t count) { return count > 0 ? static_cast<double>(sum) / count : 0.0; };
    std::printf("%s, frame %d, %dx%d, %d repeats\n", path.c_str(), frame, width, height, repeat);
    std::printf("  specular pixels: %lld (%.1f %% of the frame), tracked: %.1f %%\n",
                static_cast<long long>(tally.specularPixels), share(tally.specularPixels, int64_t{width} * height),
                share(tally.trackedPixels, tally.specularPixels));
    std::printf("  paths: %lld, static (no walk): %.1f %%, walks: %lld\n", static_cast<long long>(tally.paths),
                share(tally.unwalked, tally.paths), static_cast<long long>(tally.walks));
    std::printf("  iterations per walk: inner %.2f, outer %.2f\n", mean(tally.inner, tally.walks),
                mean(tally.outer, tally.walks));
    std::printf("  paths not tracked: %.1f %%, their share of the inner iterations: %.1f %%\n",
                share(tally.untrackedPaths, tally.paths), share(tally.untrackedInner, tally.inner));
    std::printf("  seconds per frame: %.2f wall, %.2f processor (medians)\n", median(times), median(processorTimes));
  }
  return 0;
}
