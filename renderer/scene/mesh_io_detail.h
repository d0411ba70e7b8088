#pragma once
// Internal to the mesh readers (mesh_io.cpp, obj_reader.cpp, ply_reader.cpp); not part of
// the public mesh_io.h interface.
#include <filesystem>
#include <string>
#include <string_view>

namespace pathfarm::mesh_io_detail {

// Throws a MeshError whose message is "<file>: <what>".
[[noreturn]] void fail(const std::filesystem::path& file, const std::string& what);

// A piece of file content made safe to quote in a message: bounded length, printable.
std::string quoteText(std::string_view text);

// The whole file as bytes; a MeshError names what went wrong (missing, directory, ...).
std::string readWholeFile(const std::filesystem::path& file);

}  // namespace pathfarm::mesh_io_detail
