// libFuzzer target for the mesh readers: bytes that start with PLY's magic line ("ply")
// go to the PLY reader, any others to the OBJ reader, as `loadMesh` would pick them by
// extension. Each must read into a mesh or be refused with a MeshError (which the scene
// loader turns into a SceneError); never crash, hang, leak, read out of bounds or allocate
// without limit. Built and run by bench/fuzz.sh (clang, ASan, UBSan).
#include "fuzz/fuzz_support.h"
#include "renderer/scene/mesh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view bytes = pathfarm::fuzz::asText(data, size);
  try {
    const pathfarm::TriangleMesh mesh = bytes.starts_with("ply") ? pathfarm::parsePly(bytes, "fuzz-input.ply")
                                                                 : pathfarm::parseObj(bytes, "fuzz-input.obj");
    (void)mesh;
  } catch (const pathfarm::MeshError& e) {
    pathfarm::fuzz::noteRefusal(e);
  }
  return 0;
}
