// What a worker pays per task for a shot's scene: the first render tile of a shot loads
// the scene (and, for an uploaded scene, rebuilds its files from the cache) and builds its
// ray-tracing geometry; later tiles reuse them. For comparison, the same tiles each on a
// fresh TaskRunner, which is what loading the scene per task would cost.
//
//   build/bin/task_overhead --scene FILE [--res 320x180] [--spp 1] [--tile 32] [--tiles 8] [--threads 0]
//
// Prints the first tile's time, the median of the later tiles, and the median per tile
// with a fresh runner each time; --upload serves the scene as uploaded files.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <vector>

#include "bench/command_line.h"
#include "bench/bench_support.h"
#include "bench/median.h"
#include "client/scene_upload.h"
#include "worker/task_runner.h"

namespace {

using namespace pathfarm;
using namespace pathfarm::farm;
namespace fs = std::filesystem;

// The scene's files served from memory, as a worker's cache would serve uploaded files.
struct UploadedScene {
  std::map<std::string, std::string> bytes;
  TaskRunner::ChunkFetcher fetch() const {
    return [this](const ChunkRef& ref) { return bytes.at(ref.sha256()); };
  }
};

UploadedScene upload(ShotSpec& spec) {
  const std::vector<fs::path> files = describeSceneInputs(spec);
  UploadedScene uploaded;
  for (int i = 0; i < spec.inputs_size(); ++i) {
    std::ifstream in(files[static_cast<size_t>(i)], std::ios::binary);
    uploaded.bytes[spec.inputs(i).chunk().sha256()] = std::string{std::istreambuf_iterator<char>(in), {}};
  }
  return uploaded;
}

}  // namespace

int main(int argc, char** argv) {
  bench::CommandLine app("pathfarm per-task scene overhead");
  std::string scenePath, resolution = "320x180";
  int spp = 1, tile = 32, tiles = 8, threads = 0;
  bool uploaded = false;
  app.option("--scene", scenePath).required();
  app.option("--res", resolution);
  app.option("--spp", spp);
  app.option("--tile", tile);
  app.option("--tiles", tiles).range(2, 10000);
  app.option("--threads", threads);
  app.flag("--upload", uploaded, "serve the scene as uploaded files rebuilt in a cache folder");
  if (const auto exit = app.parse(argc, argv)) return *exit;
  int width = 0, height = 0;
  if (std::sscanf(resolution.c_str(), "%dx%d", &width, &height) != 2) return 2;

  ShotSpec spec;
  spec.set_scene(scenePath);
  spec.set_width(width);
  spec.set_height(height);
  spec.set_spp(spp);
  spec.set_max_depth(8);
  spec.set_pipeline(farm::PIPELINE_PT);
  const UploadedScene files = uploaded ? upload(spec) : UploadedScene{};
  const fs::path cache = fs::temp_directory_path() / "pathfarm_task_overhead";

  std::vector<Lease> leases;
  for (int i = 0; i < tiles; ++i) {
    Lease lease;
    lease.set_shot_id(1);
    lease.set_kind(TASK_RENDER_TILE);
    *lease.mutable_spec() = spec;
    const int columns = (width + tile - 1) / tile;
    const int x0 = (i % columns) * tile, y0 = (i / columns % ((height + tile - 1) / tile)) * tile;
    farm::PixelWindow* window = lease.mutable_params()->mutable_window();
    window->set_x0(x0);
    window->set_y0(y0);
    window->set_x1(std::min(width, x0 + tile));
    window->set_y1(std::min(height, y0 + tile));
    lease.mutable_params()->set_role(ROLE_OUTPUT);
    leases.push_back(lease);
  }
  const auto runTile = [&](TaskRunner& runner, const Lease& lease) {
    std::atomic<double> progress{0};
    std::atomic<bool> abandon{false};
    return bench::seconds([&] { runner.run(lease, files.fetch(), progress, abandon); });
  };

  fs::remove_all(cache);
  TaskRunner reused(threads, cache, cache / "outgoing");
  const double first = runTile(reused, leases[0]);
  std::vector<double> later, fresh;
  for (size_t i = 1; i < leases.size(); ++i) later.push_back(runTile(reused, leases[i]));
  for (const Lease& lease : leases) {
    fs::remove_all(cache);
    TaskRunner runner(threads, cache, cache / "outgoing");
    fresh.push_back(runTile(runner, lease));
  }
  fs::remove_all(cache);
  std::printf("scene %s%s, %d tiles of %dx%d px at %d spp\n", scenePath.c_str(), uploaded ? " (uploaded)" : "",
              tiles, tile, tile, spp);
  std::printf("  first tile of the shot:        %8.3f s\n", first);
  std::printf("  later tiles (median of %zu):    %8.3f s\n", later.size(), bench::median(later));
  std::printf("  a fresh runner per tile (median of %zu): %8.3f s  -> %.1fx the reused tile\n", fresh.size(),
              bench::median(fresh), bench::median(fresh) / bench::median(later));
  return 0;
}
