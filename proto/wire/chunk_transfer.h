#pragma once
// Moving a chunk over a gRPC stream in bounded parts: the first part carries the
// reference (digest and size), the receiver checks both before it believes the bytes.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "pathfarm/chunk.pb.h"
#include "proto/wire/chunk_store.h"
#include "proto/wire/sha256.h"

namespace pathfarm::farm {

// Bytes per part; with the headers a part stays well under kMaxMessageBytes.
inline constexpr size_t kChunkPartBytes = 1 << 20;

// Sends a chunk whose bytes `read` hands to its argument in parts of at most
// kChunkPartBytes, as ChunkStore::readParts does (a false from the argument stops it and
// makes it return false). The first part carries `ref`; an empty chunk is one empty part.
// `Writer` is any gRPC stream with Write(const ChunkPart&) -> bool.
template <class Writer, class ReadParts>
bool sendParts(Writer& writer, const ChunkRef& ref, ReadParts read) {
  bool first = true;
  const auto write = [&](std::string_view data) {
    ChunkPart part;
    if (first) *part.mutable_ref() = ref;
    first = false;
    part.set_data(data.data(), data.size());
    return writer.Write(part);
  };
  if (!read(std::function<bool(std::string_view)>(write))) return false;
  return !first || write({});
}

template <class Writer>
bool sendChunk(Writer& writer, const ChunkRef& ref, const std::string& bytes) {
  return sendParts(writer, ref, [&](const std::function<bool(std::string_view)>& part) {
    for (size_t offset = 0; offset < bytes.size(); offset += kChunkPartBytes)
      if (!part(std::string_view(bytes).substr(offset, kChunkPartBytes))) return false;
    return true;
  });
}

// Sends a file's bytes, `ref` being their digest and size (refOfFile), never holding them
// whole. Throws ChunkError when the file cannot be read.
template <class Writer>
bool sendFileChunk(Writer& writer, const ChunkRef& ref, const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw ChunkError("cannot read " + file.string());
  return sendParts(writer, ref, [&](const std::function<bool(std::string_view)>& part) {
    return readStreamParts(in, kChunkPartBytes, part);
  });
}

// Sends a stored chunk in parts after checking its digest, never holding it whole.
// Absent: the store has no intact copy (a damaged file is removed).
enum class StoredSend { Sent, Absent, ReaderGone };
template <class Writer>
StoredSend sendStoredChunk(Writer& writer, const ChunkStore& store, const std::string& sha256) {
  const std::optional<int64_t> size = store.verifiedSize(sha256);
  if (!size) return StoredSend::Absent;
  ChunkRef ref;
  ref.set_sha256(sha256);
  ref.set_size(*size);
  const bool sent = sendParts(writer, ref, [&](const std::function<bool(std::string_view)>& part) {
    return store.readParts(sha256, kChunkPartBytes, part);
  });
  return sent ? StoredSend::Sent : StoredSend::ReaderGone;
}

// Writes a chunk streamed in parts into the store as it arrives (never holding it whole)
// and returns its reference. Throws ChunkError when the bytes do not match the announced
// reference, exceed `maxBytes` or cannot be stored.
template <class Reader>
ChunkRef receiveChunkIntoStore(Reader& reader, ChunkStore& store, size_t maxBytes) {
  ChunkPart part;
  if (!reader.Read(&part)) throw ChunkError("empty chunk stream");
  ChunkStore::Incoming incoming(store, part.ref(), maxBytes);
  do {
    incoming.append(part.data());
  } while (reader.Read(&part));
  return incoming.commit();
}

// Collects one chunk's parts and checks them against the announced reference.
class ChunkAssembler {
 public:
  // Throws ChunkError when the announced size exceeds `maxBytes`.
  void start(const ChunkRef& ref, size_t maxBytes);
  // Throws ChunkError when the bytes outgrow the announced size.
  void append(const std::string& data);
  bool started() const { return started_; }
  const ChunkRef& ref() const { return ref_; }
  // The verified bytes; throws ChunkError for a short chunk or a digest mismatch.
  std::string finish();

 private:
  ChunkRef ref_;
  std::string bytes_;
  bool started_ = false;
};

// `Reader` is any gRPC stream with Read(ChunkPart*) -> bool. Throws ChunkError when the
// bytes do not match the announced reference or exceed `maxBytes`.
template <class Reader>
std::string receiveChunk(Reader& reader, ChunkRef& ref, size_t maxBytes) {
  ChunkAssembler chunk;
  ChunkPart part;
  while (reader.Read(&part)) {
    if (!chunk.started()) chunk.start(part.ref(), maxBytes);
    chunk.append(part.data());
  }
  if (!chunk.started()) throw ChunkError("empty chunk stream");
  ref = chunk.ref();
  return chunk.finish();
}

}  // namespace pathfarm::farm
