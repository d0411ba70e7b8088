#include "scheduler/shot_file.h"

#include <fstream>
#include <sstream>

#include "renderer/decomposition/auto_decomposition.h"
#include "renderer/scene/json_node.h"
#include "renderer/scene/scene_loader.h"

namespace pathfarm::farm {

ShotSpec loadShotFile(const std::filesystem::path& file) {
  const std::string label = file.string();
  std::ifstream in(file);
  if (!in) throw SceneError(label + ": cannot open the shot file");
  std::ostringstream text;
  text << in.rdbuf();
  nlohmann::json document;
  try {
    document = nlohmann::json::parse(text.str());
  } catch (const nlohmann::json::parse_error& e) {
    throw SceneError(label + ": invalid JSON: " + e.what());
  }
  const JsonNode root(document, "", label);
  root.expectKeys({"name", "scene", "frames", "resolution", "spp", "max_depth", "pipeline", "tile", "output",
                   "priority", "max_attempts", "noop_tasks", "decompose"});
  const std::filesystem::path folder = std::filesystem::absolute(file).parent_path();

  ShotSpec spec;
  spec.set_name(root.has("name") ? root["name"].string() : file.stem().string());
  spec.set_pipeline(root.has("pipeline") ? root["pipeline"].string() : "pt");
  if (spec.pipeline() != "pt" && spec.pipeline() != "noop")
    root["pipeline"].fail("unknown pipeline \"" + spec.pipeline() + "\" (this farm runs: pt, noop)");
  spec.set_priority(root.has("priority") ? root["priority"].integer(-1000, 1000) : 0);
  spec.set_max_attempts(root.has("max_attempts") ? root["max_attempts"].integer(1, 100) : 3);
  spec.set_tile(root.has("tile") ? root["tile"].integer(8, 4096) : 64);
  spec.set_output((folder / (root.has("output") ? root["output"].string() : "output/" + spec.name()))
                      .lexically_normal()
                      .string());
  if (spec.pipeline() == "noop") {
    spec.set_noop_tasks(root["noop_tasks"].integer(1, 10'000'000));
    return spec;
  }

  const JsonNode sceneKey = root["scene"];
  const std::filesystem::path scenePath = (folder / sceneKey.string()).lexically_normal();
  const Scene scene = loadScene(scenePath);  // throws SceneError naming the scene file
  spec.set_scene(scenePath.string());
  spec.set_frame_start(scene.defaults.frameStart);
  spec.set_frame_end(scene.defaults.frameEnd);
  if (auto frames = root.optional("frames")) {
    frames->expectKeys({"start", "end"});
    spec.set_frame_start((*frames)["start"].integer(0, 10'000'000));
    spec.set_frame_end((*frames)["end"].integer(static_cast<int>(spec.frame_start()), 10'000'000));
  }
  spec.set_width(scene.defaults.width);
  spec.set_height(scene.defaults.height);
  if (auto resolution = root.optional("resolution")) {
    const auto e = resolution->elements();
    if (e.size() != 2) resolution->fail("expected [width, height]");
    spec.set_width(e[0].integer(1, 16384));
    spec.set_height(e[1].integer(1, 16384));
  }
  spec.set_spp(root.has("spp") ? root["spp"].integer(1, 1 << 20) : scene.defaults.spp);
  spec.set_max_depth(root.has("max_depth") ? root["max_depth"].integer(0, 1024) : scene.defaults.maxDepth);
  if (auto decompose = root.optional("decompose")) {
    try {
      // Resolved here, once: every worker then splits the frames the same way.
      const auto decomposition = decompositionFor(scene, decompose->string());
      spec.set_decompose(decomposition ? decomposition->describe() : "none");
    } catch (const std::invalid_argument& e) {
      decompose->fail(e.what());
    }
  }
  return spec;
}

}  // namespace pathfarm::farm
