#include "proto/wire/chunk_store.h"

#include <fstream>
#include <sstream>

#include "image/atomic_file.h"
#include "proto/wire/sha256.h"

namespace pathfarm::farm {
namespace {

// The digest and size of what is left in `in`.
ChunkRef refOfStream(std::istream& in) {
  Sha256 digest;
  int64_t size = 0;
  readStreamParts(in, size_t{1} << 20, [&](std::string_view part) {
    digest.update(part);
    size += static_cast<int64_t>(part.size());
    return true;
  });
  ChunkRef ref;
  ref.set_sha256(digest.hex());
  ref.set_size(size);
  return ref;
}

}  // namespace

bool isSha256Hex(const std::string& text) {
  return text.size() == 64 &&
         text.find_first_not_of("0123456789abcdef") == std::string::npos;
}

ChunkStore::ChunkStore(std::filesystem::path root, Kind kind)
    : root_(std::move(root)), sync_(kind == Kind::Cache ? AtomicFileWriter::Sync::No : AtomicFileWriter::Sync::Yes) {
  std::filesystem::create_directories(root_ / "objects");
}

size_t ChunkStore::removeAbandonedWrites() {
  size_t removed = 0;
  std::error_code error;
  for (const auto& folder : std::filesystem::directory_iterator(root_ / "objects", error))
    if (folder.is_directory(error)) removed += removeAbandonedTemporaries(folder.path());
  return removed;
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
    writeFileAtomically(target, bytes, sync_);
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

IncomingChunk::IncomingChunk(const ChunkRef& announced, size_t maxBytes, const std::optional<std::filesystem::path>& file,
                             AtomicFileWriter::Sync sync, std::string purpose)
    : announced_(announced), sync_(sync), purpose_(std::move(purpose)), digest_(std::make_unique<Sha256>()) {
  if (announced.size() < 0 || static_cast<uint64_t>(announced.size()) > maxBytes)
    throw ChunkError("chunk of " + std::to_string(announced.size()) + " bytes exceeds the limit of " +
                     std::to_string(maxBytes));
  if (!isSha256Hex(announced.sha256())) throw ChunkError("a chunk must announce its SHA-256 digest");
  if (!file) return;
  try {
    std::filesystem::create_directories(file->parent_path());
    file_ = std::make_unique<AtomicFileWriter>(*file);
  } catch (const std::exception& e) {
    fail(e);
  }
}

IncomingChunk::~IncomingChunk() = default;

void IncomingChunk::fail(const std::exception& e) const {
  throw ChunkError("cannot " + purpose_ + ": " + e.what());
}

void IncomingChunk::append(std::string_view part) {
  received_ += static_cast<int64_t>(part.size());
  if (received_ > announced_.size())
    throw ChunkError("chunk longer than its announced " + std::to_string(announced_.size()) + " bytes");
  digest_->update(part);
  if (!file_) return;
  try {
    file_->append(part);
  } catch (const std::exception& e) {
    file_.reset();
    fail(e);
  }
}

ChunkRef IncomingChunk::commit() {
  if (received_ != announced_.size())
    throw ChunkError("chunk truncated: " + std::to_string(received_) + " of " + std::to_string(announced_.size()) +
                     " bytes");
  const std::string digest = digest_->hex();
  if (digest != announced_.sha256())
    throw ChunkError("chunk digest mismatch: announced " + announced_.sha256() + ", received " + digest);
  if (file_) {
    try {
      file_->commit(sync_);
    } catch (const std::exception& e) {
      fail(e);
    }
  }
  return announced_;
}

namespace {

// Where an arriving chunk is written: nowhere when the store has it already (its bytes
// are checked all the same) or its digest is no name (IncomingChunk refuses it).
std::optional<std::filesystem::path> arrivalPath(const ChunkStore& store, const std::string& sha256) {
  if (!isSha256Hex(sha256) || store.has(sha256)) return std::nullopt;
  return store.pathOf(sha256);
}

}  // namespace

ChunkStore::Incoming::Incoming(ChunkStore& store, const ChunkRef& announced, size_t maxBytes)
    : store_(store),
      chunk_(announced, maxBytes, arrivalPath(store, announced.sha256()), store.sync_, "store chunk") {}

ChunkRef ChunkStore::Incoming::commit() {
  const ChunkRef ref = chunk_.commit();
  store_.bytesIn_ += static_cast<uint64_t>(ref.size());
  return ref;
}

std::optional<int64_t> ChunkStore::verifiedSize(const std::string& sha256) const {
  if (!isSha256Hex(sha256)) return std::nullopt;
  std::ifstream in(pathOf(sha256), std::ios::binary);
  if (!in) return std::nullopt;
  const ChunkRef found = refOfStream(in);
  if (found.sha256() == sha256) return found.size();
  std::error_code ignored;
  std::filesystem::remove(pathOf(sha256), ignored);
  return std::nullopt;
}

bool ChunkStore::readParts(const std::string& sha256, size_t partBytes,
                           const std::function<bool(std::string_view)>& part) const {
  std::ifstream in(pathOf(sha256), std::ios::binary);
  return readStreamParts(in, partBytes, [&](std::string_view data) {
    bytesOut_ += data.size();
    return part(data);
  });
}

void ChunkStore::remove(const std::string& sha256) {
  if (!isSha256Hex(sha256)) return;
  std::error_code ignored;
  std::filesystem::remove(pathOf(sha256), ignored);
}

bool readStreamParts(std::istream& in, size_t partBytes, const std::function<bool(std::string_view)>& part) {
  std::string buffer(partBytes, '\0');
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    const auto n = static_cast<size_t>(in.gcount());
    if (n == 0) break;
    if (!part(std::string_view(buffer.data(), n))) return false;
  }
  return true;
}

ChunkRef refOfFile(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw ChunkError("cannot read " + file.string());
  ChunkRef ref = refOfStream(in);
  if (in.bad()) throw ChunkError("cannot read " + file.string());
  return ref;
}

}  // namespace pathfarm::farm
