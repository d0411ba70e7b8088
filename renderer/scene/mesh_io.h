#pragma once
// Triangle meshes from Wavefront OBJ and Stanford PLY files. Polygons are triangulated,
// per-vertex normals and uvs are kept when the file has them.
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

#include "renderer/scene/mesh.h"

namespace pathfarm {

// Thrown for a missing, unreadable or malformed mesh file; the message names the file
// and what is wrong (e.g. "bunny.ply: face 12 refers to vertex 9000 of 4000").
class MeshError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Chooses the reader from the extension (.obj or .ply, case-insensitive).
TriangleMesh loadMesh(const std::filesystem::path& file);
TriangleMesh loadObj(const std::filesystem::path& file);
TriangleMesh loadPly(const std::filesystem::path& file);
// The same readers on a file's bytes already in memory; `file` only names it in messages.
TriangleMesh parseObj(std::string_view data, const std::filesystem::path& file);
TriangleMesh parsePly(std::string_view data, const std::filesystem::path& file);

}  // namespace pathfarm
