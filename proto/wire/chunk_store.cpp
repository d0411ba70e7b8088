#include "proto/wire/chunk_store.h"

#include <fstream>
#include <sstream>

#include "image/atomic_file.h"
#include "proto/wire/sha256.h"

namespace pathfarm::farm {

bool isSha256Hex(const std::string& text) {
  return text.size() == 64 &&
         text.find_first_not_of("0123456789abcdef") == std::string::npos;
}

ChunkStore::ChunkStore(std::filesystem::path root) : root_(std::move(root)) {
  std::filesystem::create_directories(root_ / "objects");
}

std::filesystem::path ChunkStore::pathOf(const std::string& sha256) const {
  return root_ / "objects" / sha256.substr(0, 2) / sha256.substr(2);
}

ChunkRef ChunkStore::put(const std::string& bytes, const ChunkRef& expected) {
  ChunkRef ref;
  ref.set_sha256(sha256Hex(bytes));
  ref.set_size(static_cast<int64_t>(bytes.size()));
  if (!expected.sha256().empty() && expected.sha256() != ref.sha256())
    throw ChunkError("chunk digest mismatch: announced " + expected.sha256() + ", received " + ref.sha256());
  if (expected.size() != 0 && expected.size() != ref.size())
    throw ChunkError("chunk size mismatch: announced " + std::to_string(expected.size()) + " bytes, received " +
                     std::to_string(ref.size()));
  bytesIn_ += bytes.size();
  if (has(ref.sha256())) return ref;
  const auto target = pathOf(ref.sha256());
  try {
    std::filesystem::create_directories(target.parent_path());
    // Two writers of one chunk write the same bytes, each through its own temporary.
    writeFileAtomically(target, bytes);
  } catch (const std::exception& e) {
    throw ChunkError(std::string("cannot store chunk: ") + e.what());
  }
  return ref;
}

bool ChunkStore::has(const std::string& sha256) const {
  return isSha256Hex(sha256) && std::filesystem::exists(pathOf(sha256));
}

std::optional<std::string> ChunkStore::get(const std::string& sha256) const {
  if (!isSha256Hex(sha256)) return std::nullopt;
  std::ifstream in(pathOf(sha256), std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream bytes;
  bytes << in.rdbuf();
  std::string data = bytes.str();
  if (sha256Hex(data) != sha256) {
    std::error_code ignored;
    std::filesystem::remove(pathOf(sha256), ignored);
    return std::nullopt;
  }
  bytesOut_ += data.size();
  return data;
}

void ChunkStore::remove(const std::string& sha256) {
  if (!isSha256Hex(sha256)) return;
  std::error_code ignored;
  std::filesystem::remove(pathOf(sha256), ignored);
}

}  // namespace pathfarm::farm
