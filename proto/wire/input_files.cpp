#include "proto/wire/input_files.h"

#include <algorithm>
#include <set>
#include <stdexcept>
#include <vector>

#include "proto/wire/chunk_store.h"
#include "proto/wire/connection.h"
#include "proto/wire/sha256.h"

namespace pathfarm::farm {
namespace {

constexpr size_t kMaxPathLength = 1024;
constexpr int kMaxInputFiles = 100000;

}  // namespace

bool isSafeInputPath(const std::string& path) {
  if (path.empty() || path.size() > kMaxPathLength || path.front() == '/') return false;
  if (path.find('\\') != std::string::npos || path.find('\0') != std::string::npos) return false;
  size_t start = 0;
  for (;;) {
    const size_t slash = path.find('/', start);
    const std::string part = path.substr(start, slash == std::string::npos ? std::string::npos : slash - start);
    if (part.empty() || part == "." || part == "..") return false;
    if (slash == std::string::npos) return true;
    start = slash + 1;
  }
}

void checkInputFiles(const ShotSpec& spec) {
  if (spec.inputs().empty()) return;
  if (spec.inputs_size() > kMaxInputFiles)
    throw std::invalid_argument("a shot may name at most " + std::to_string(kMaxInputFiles) + " scene files");
  std::set<std::string> paths;
  for (const InputFile& file : spec.inputs()) {
    if (!isSafeInputPath(file.path()))
      throw std::invalid_argument("scene file \"" + file.path() + "\": not a relative path inside the scene's folder");
    if (!paths.insert(file.path()).second)
      throw std::invalid_argument("scene file \"" + file.path() + "\" is named twice");
    if (!isSha256Hex(file.chunk().sha256()) || file.chunk().size() < 0 ||
        static_cast<size_t>(file.chunk().size()) > kMaxChunkBytes)
      throw std::invalid_argument("scene file \"" + file.path() + "\": not a valid chunk reference");
  }
  if (!paths.count(spec.scene()))
    throw std::invalid_argument("the scene \"" + spec.scene() + "\" is not among the shot's uploaded files");
}

std::string inputFilesDigest(const ShotSpec& spec) {
  std::vector<std::string> lines;
  for (const InputFile& file : spec.inputs()) lines.push_back(file.path() + '\0' + file.chunk().sha256() + '\n');
  std::sort(lines.begin(), lines.end());
  std::string text = spec.scene() + '\n';
  for (const std::string& line : lines) text += line;
  return sha256Hex(text);
}

}  // namespace pathfarm::farm
