// libFuzzer target for the scene loader: any bytes, as a scene JSON file in fuzz/assets
// (so it may name the meshes, texture, sky and glTF file there), must load into a scene or
// be refused with a SceneError, which `pathfarm render` reports with exit status 2; never
// crash, hang, leak, read out of bounds or allocate without limit. Built and run by
// bench/fuzz.sh (clang, ASan, UBSan).
#include "fuzz/fuzz_support.h"
#include "renderer/scene/scene_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  pathfarm::fuzz::silenceLogs();
  try {
    const pathfarm::Scene scene =
        pathfarm::parseScene(pathfarm::fuzz::asText(data, size), pathfarm::fuzz::assetFolder() / "fuzz-input.json");
    (void)scene;
  } catch (const pathfarm::SceneError& e) {
    pathfarm::fuzz::noteRefusal(e);
  }
  return 0;
}
