// libFuzzer target for the glTF importer: any bytes, as a .gltf or .glb, must load into
// a scene or be refused with a SceneError; never crash, hang, read out of bounds or
// allocate without limit. Built and run by bench/fuzz.sh (clang, ASan, UBSan).
#include "fuzz/fuzz_support.h"
#include "renderer/scene/gltf/gltf_document.h"
#include "renderer/scene/gltf/gltf_scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  pathfarm::fuzz::silenceLogs();
  try {
    // External URIs resolve in a folder that does not exist: the input is the whole file.
    const pathfarm::GltfDocument document(data, size, "fuzz-input", "/nonexistent-pathfarm-fuzz");
    pathfarm::GltfImportOptions options;
    options.requireCamera = false;
    const pathfarm::Scene scene = pathfarm::importGltfScene(document, options);
    (void)scene;
  } catch (const pathfarm::SceneError& e) {
    pathfarm::fuzz::noteRefusal(e);
  }
  return 0;
}
