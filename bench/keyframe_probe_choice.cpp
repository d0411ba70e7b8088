// The keyframe probe's choice for a dui shot of each scene (client/keyframe_probe.h),
// without running the shot: the interval and the re-render rate it predicts for every
// interval it tried, as the shot's report would give them. docs/performance.md, "dui
// interpolates under a moving camera", tabulates it.
//
//   build/bin/keyframe_probe_choice [--scenes dolly,courtyard,walkthrough,cornell,showroom,creature]
//                                   [--res 320x180] [--frames 0:23] [--spp 64] [--root .]
//
// A scene is the folder scenes/NAME under --root (its scene.json).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "bench/command_line.h"
#include "client/shot_preparation.h"

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  using namespace pathfarm;
  bench::CommandLine app("the keyframe probe's choice for a dui shot of each scene");
  std::vector<std::string> scenes = {"dolly", "courtyard", "walkthrough", "cornell", "showroom", "creature"};
  std::string resolution = "320x180", frames = "0:23", root = ".";
  int spp = 64;
  app.option("--scenes", scenes).commaSeparated();
  app.option("--res", resolution, "WIDTHxHEIGHT");
  app.option("--frames", frames, "FIRST:LAST");
  app.option("--spp", spp).positive();
  app.option("--root", root, "the repository, which holds scenes/");
  if (const auto exit = app.parse(argc, argv)) return *exit;
  int width = 0, height = 0;
  long long first = 0, last = 0;
  if (std::sscanf(resolution.c_str(), "%dx%d", &width, &height) != 2 ||
      std::sscanf(frames.c_str(), "%lld:%lld", &first, &last) != 2) {
    std::fprintf(stderr, "keyframe_probe_choice: --res is WIDTHxHEIGHT and --frames FIRST:LAST\n");
    return 2;
  }
  spdlog::set_level(spdlog::level::warn);  // the table alone on standard output
  return app.run([&] {
    const fs::path shotFile = fs::temp_directory_path() / "pathfarm_keyframe_probe_choice.json";
    std::printf("| scene | resolution | k | the probe's reason |\n| --- | --- | ---: | --- |\n");
    for (const std::string& scene : scenes) {
      const fs::path sceneFile = fs::absolute(fs::path(root) / "scenes" / scene / "scene.json");
      std::ofstream(shotFile) << "{\"scene\": \"" << sceneFile.string() << "\", \"frames\": {\"start\": " << first
                              << ", \"end\": " << last << "}, \"resolution\": [" << width << ", " << height
                              << "], \"spp\": " << spp << ", \"pipeline\": \"dui\"}";
      const farm::ShotSpec spec = farm::loadShotFile(shotFile);
      std::printf("| %s | %dx%d | %d | %s |\n", scene.c_str(), width, height, spec.keyframe_interval(),
                  spec.keyframe_reason().c_str());
      std::fflush(stdout);
    }
    fs::remove(shotFile);
    return 0;
  });
}
