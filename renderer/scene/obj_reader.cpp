// Wavefront OBJ reader, on top of tinyobjloader.
#include <tiny_obj_loader.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <string_view>
#include <unordered_map>

#include "renderer/scene/mesh_io.h"
#include "renderer/scene/mesh_io_detail.h"

namespace pathfarm {

namespace fs = std::filesystem;

using mesh_io_detail::fail;
using mesh_io_detail::readWholeFile;

namespace {

struct ObjCorner {
  int v, n, t;
  bool operator==(const ObjCorner&) const = default;
};

struct ObjCornerHash {
  size_t operator()(const ObjCorner& c) const {
    uint64_t h = static_cast<uint32_t>(c.v);
    h = h * 0x9E3779B97F4A7C15ull ^ static_cast<uint32_t>(c.n);
    h = h * 0x9E3779B97F4A7C15ull ^ static_cast<uint32_t>(c.t);
    return static_cast<size_t>(h ^ (h >> 29));
  }
};

// Element `index` (0-based) of a flat x, y, z array; refused, named 1-based as OBJ counts,
// when not finite.
Vec3f finiteVec3(const std::vector<tinyobj::real_t>& values, int index, const std::filesystem::path& file,
                 const char* what, const char* notFinite) {
  const auto i = static_cast<size_t>(index) * 3;
  const Vec3f v{values[i], values[i + 1], values[i + 2]};
  if (!isFinite(v)) fail(file, std::string(what) + " " + std::to_string(index + 1) + " " + notFinite);
  return v;
}

std::string firstLine(const std::string& text) {
  std::string line = text.substr(0, text.find('\n'));
  while (!line.empty() && (line.back() == '\r' || line.back() == '.' || line.back() == ' '))
    line.pop_back();
  return line.empty() ? std::string("unknown error") : line;
}

// Calls visit(start, end, lineNumber) for each line [start, end) of `text` as
// tinyobjloader splits them: at "\n", "\r" or "\r\n".
template <class Visit>
void forEachLine(std::string_view text, Visit visit) {
  size_t lineNumber = 1;
  for (size_t start = 0; start < text.size(); ++lineNumber) {
    const size_t end = std::min(text.find_first_of("\r\n", start), text.size());
    visit(start, end, lineNumber);
    start = end + (text.compare(end, 2, "\r\n") == 0 ? 2 : 1);
  }
}

// tinyobjloader reads a number it cannot parse ("nan", "1e999", "x") as 0 without a word,
// which would move a vertex silently: every number of a v, vn and vt line must be finite.
void refuseUnreadableNumbers(const fs::path& file, const std::string& text) {
  forEachLine(text, [&](size_t start, size_t end, size_t lineNumber) {
    const std::string line = text.substr(start, end - start);
    std::istringstream words(line.substr(0, line.find('#')));
    std::string keyword, word;
    if (!(words >> keyword) || (keyword != "v" && keyword != "vn" && keyword != "vt")) return;
    while (words >> word) {
      double value = 0;
      const auto [rest, error] = std::from_chars(word.data(), word.data() + word.size(), value);
      if (error != std::errc() || rest != word.data() + word.size() || !std::isfinite(value))
        fail(file, "line " + std::to_string(lineNumber) + ": \"" + word + "\" is not a finite number");
    }
  });
}

// tinyobjloader's own `vw` lines (skin weights, which pathfarm does not use) convert a joint
// id to int unchecked: "vw 0 1e35 1" is undefined behaviour (found by bench/fuzz.sh
// --target mesh_readers). They are turned into comments before it reads them.
void dropSkinWeights(std::string& text) {
  forEachLine(text, [&](size_t start, size_t end, size_t) {
    const size_t keyword = std::min(text.find_first_not_of(" \t", start), end);
    if (end - keyword >= 3 && text.compare(keyword, 2, "vw") == 0 &&
        (text[keyword + 2] == ' ' || text[keyword + 2] == '\t'))
      text[keyword] = '#';
  });
}

}  // namespace

TriangleMesh loadObj(const fs::path& file) { return parseObj(readWholeFile(file), file); }

TriangleMesh parseObj(std::string_view data, const fs::path& file) {
  std::string text(data);
  refuseUnreadableNumbers(file, text);
  dropSkinWeights(text);

  // Parsed from memory with an empty material library: materials are not ours to load
  // here, and this keeps `mtllib` lines from opening other files.
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  if (!reader.ParseFromString(text, std::string(), config)) {
    fail(file, "malformed OBJ: " + firstLine(reader.Error()));
  }

  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  const auto positionCount = static_cast<long long>(attrib.vertices.size() / 3);
  const auto normalCount = static_cast<long long>(attrib.normals.size() / 3);
  const auto uvCount = static_cast<long long>(attrib.texcoords.size() / 2);

  // Validate every corner, and find out whether all of them carry normals and uvs.
  bool allNormals = true, allUvs = true;
  size_t cornerCount = 0;
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    for (const tinyobj::index_t& idx : shape.mesh.indices) {
      if (idx.vertex_index < 0) {
        fail(file, "a face refers to a vertex before the first one (relative index out of range)");
      }
      if (idx.vertex_index >= positionCount) {
        fail(file, "a face refers to vertex " + std::to_string(idx.vertex_index + 1LL) + " of " +
                       std::to_string(positionCount));
      }
      if (idx.normal_index < -1 || idx.normal_index >= normalCount) {
        fail(file, "a face refers to normal " + std::to_string(idx.normal_index + 1LL) + " of " +
                       std::to_string(normalCount));
      }
      if (idx.texcoord_index < -1 || idx.texcoord_index >= uvCount) {
        fail(file, "a face refers to texture coordinate " +
                       std::to_string(idx.texcoord_index + 1LL) + " of " + std::to_string(uvCount));
      }
      allNormals = allNormals && idx.normal_index >= 0;
      allUvs = allUvs && idx.texcoord_index >= 0;
    }
    cornerCount += shape.mesh.indices.size();
  }
  // tinyobjloader silently drops some faces with bad indices (it only warns).
  const std::string& warning = reader.Warning();
  if (warning.find("out of bounds") != std::string::npos ||
      warning.find("invalid vertex index") != std::string::npos) {
    fail(file, "a face refers to a vertex that does not exist");
  }
  if (cornerCount == 0) fail(file, "no faces");

  TriangleMesh mesh;
  std::unordered_map<ObjCorner, uint32_t, ObjCornerHash> vertexOf;
  mesh.indices.reserve(cornerCount);
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    for (const tinyobj::index_t& idx : shape.mesh.indices) {
      const ObjCorner key{idx.vertex_index, allNormals ? idx.normal_index : -1,
                          allUvs ? idx.texcoord_index : -1};
      const auto [it, inserted] =
          vertexOf.try_emplace(key, static_cast<uint32_t>(mesh.positions.size()));
      if (inserted) {
        mesh.positions.push_back(finiteVec3(attrib.vertices, key.v, file, "vertex", "has a non-finite position"));
        if (allNormals) mesh.normals.push_back(finiteVec3(attrib.normals, key.n, file, "normal", "is not finite"));
        if (allUvs) {
          const auto t = static_cast<size_t>(key.t) * 2;
          const Vec2f uv{attrib.texcoords[t], attrib.texcoords[t + 1]};
          if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) {
            fail(file, "texture coordinate " + std::to_string(key.t + 1) + " is not finite");
          }
          mesh.uvs.push_back(uv);
        }
      }
      mesh.indices.push_back(it->second);
    }
  }
  if (mesh.indices.size() % 3 != 0) fail(file, "faces could not be triangulated");
  return mesh;
}

}  // namespace pathfarm
