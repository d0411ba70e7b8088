#include "renderer/scene/mesh_io.h"

#include <fstream>
#include <ios>
#include <limits>
#include <string>
#include <string_view>
#include <system_error>

#include "renderer/scene/mesh_io_detail.h"
#include "renderer/scene/scene_inputs.h"

namespace pathfarm {

namespace fs = std::filesystem;

namespace mesh_io_detail {

[[noreturn]] void fail(const fs::path& file, const std::string& what) {
  throw MeshError(file.string() + ": " + what);
}

// A piece of file content made safe to quote in a message: bounded length, printable.
std::string quoteText(std::string_view text) {
  constexpr size_t kMax = 40;
  std::string out = "'";
  for (size_t i = 0; i < text.size() && i < kMax; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    out += (c >= 0x20 && c < 0x7f) ? static_cast<char>(c) : '?';
  }
  if (text.size() > kMax) out += "...";
  out += "'";
  return out;
}

std::string readWholeFile(const fs::path& file) {
  std::error_code ec;
  const fs::file_status status = fs::status(file, ec);
  if (status.type() == fs::file_type::not_found) fail(file, "no such file");
  if (ec) fail(file, "cannot access the file (" + ec.message() + ")");
  if (fs::is_directory(status)) fail(file, "is a directory, not a mesh file");
  if (!fs::is_regular_file(status)) fail(file, "is not a regular file");
  const uintmax_t size = fs::file_size(file, ec);
  if (ec) fail(file, "cannot determine the file size (" + ec.message() + ")");
  if (size > static_cast<uintmax_t>(std::numeric_limits<std::streamsize>::max())) {
    fail(file, "file is too large");
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file, "cannot open the file for reading");
  noteSceneInput(file);
  std::string data(static_cast<size_t>(size), '\0');
  in.read(data.data(), static_cast<std::streamsize>(size));
  if (in.gcount() != static_cast<std::streamsize>(size)) fail(file, "cannot read the file");
  return data;
}

}  // namespace mesh_io_detail

using mesh_io_detail::fail;
using mesh_io_detail::quoteText;

namespace {

std::string lowercase(std::string s) {
  for (char& c : s) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return s;
}

}  // namespace

TriangleMesh loadMesh(const fs::path& file) {
  const std::string ext = lowercase(file.extension().string());
  if (ext == ".obj") return loadObj(file);
  if (ext == ".ply") return loadPly(file);
  fail(file, "unsupported mesh file extension " +
                 (ext.empty() ? std::string("(none)") : quoteText(ext)) +
                 ", expected .obj or .ply");
}

}  // namespace pathfarm
