#include "proto/wire/chunk_transfer.h"

namespace pathfarm::farm {

void ChunkAssembler::start(const ChunkRef& ref, size_t maxBytes) {
  if (ref.size() < 0 || static_cast<size_t>(ref.size()) > maxBytes)
    throw ChunkError("chunk of " + std::to_string(ref.size()) + " bytes exceeds the limit of " +
                     std::to_string(maxBytes));
  ref_ = ref;
  bytes_.clear();
  bytes_.reserve(static_cast<size_t>(ref.size()));
  started_ = true;
}

void ChunkAssembler::append(const std::string& data) {
  if (bytes_.size() + data.size() > static_cast<size_t>(ref_.size()))
    throw ChunkError("chunk longer than its announced " + std::to_string(ref_.size()) + " bytes");
  bytes_ += data;
}

std::string ChunkAssembler::finish() {
  started_ = false;
  if (bytes_.size() != static_cast<size_t>(ref_.size()))
    throw ChunkError("chunk truncated: " + std::to_string(bytes_.size()) + " of " + std::to_string(ref_.size()) +
                     " bytes");
  if (sha256Hex(bytes_) != ref_.sha256()) throw ChunkError("chunk digest mismatch for " + ref_.sha256());
  return std::move(bytes_);
}

}  // namespace pathfarm::farm
