#include <gtest/gtest.h>

#include <fstream>

#include "proto/wire/chunk_store.h"
#include "proto/wire/chunk_transfer.h"

namespace pathfarm::farm {
namespace {

std::filesystem::path freshFolder(const std::string& name) {
  const auto folder = std::filesystem::temp_directory_path() / ("pathfarm_chunks_" + name);
  std::filesystem::remove_all(folder);
  return folder;
}

TEST(Sha256, MatchesKnownDigests) {
  EXPECT_EQ(sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

TEST(ChunkStore, StoresByContentAndVerifiesOnRead) {
  const auto folder = freshFolder("store");
  ChunkStore store(folder);
  const std::string bytes = "some EXR bytes";
  const ChunkRef ref = store.put(bytes);
  EXPECT_EQ(ref.sha256(), sha256Hex(bytes));
  EXPECT_TRUE(store.has(ref.sha256()));
  EXPECT_EQ(store.get(ref.sha256()).value(), bytes);
  EXPECT_EQ(store.put(bytes).sha256(), ref.sha256());  // idempotent

  // A file damaged on disk is not served.
  const auto file = folder / "objects" / ref.sha256().substr(0, 2) / ref.sha256().substr(2);
  std::ofstream(file, std::ios::binary | std::ios::trunc) << "tampered";
  EXPECT_FALSE(store.get(ref.sha256()).has_value());
  EXPECT_FALSE(store.get("../../etc/passwd").has_value());
  std::filesystem::remove_all(folder);
}

TEST(ChunkStore, RefusesBytesThatDoNotMatchTheirAnnouncement) {
  const auto folder = freshFolder("mismatch");
  ChunkStore store(folder);
  ChunkRef announced;
  announced.set_sha256(sha256Hex("other bytes"));
  EXPECT_THROW(store.put("these bytes", announced), ChunkError);
  EXPECT_FALSE(store.has(sha256Hex("these bytes")));
  std::filesystem::remove_all(folder);
}

// A stream of parts as gRPC would deliver them.
struct PartStream {
  std::vector<ChunkPart> parts;
  size_t next = 0;
  bool Write(const ChunkPart& part) {
    parts.push_back(part);
    return true;
  }
  bool Read(ChunkPart* part) {
    if (next == parts.size()) return false;
    *part = parts[next++];
    return true;
  }
};

TEST(ChunkTransfer, LargeChunksTravelInBoundedVerifiedParts) {
  std::string bytes(3 * kChunkPartBytes + 123, '\0');
  for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<char>(i * 7919 % 251);
  ChunkRef ref;
  ref.set_sha256(sha256Hex(bytes));
  ref.set_size(static_cast<int64_t>(bytes.size()));
  PartStream stream;
  ASSERT_TRUE(sendChunk(stream, ref, bytes));
  EXPECT_EQ(stream.parts.size(), 4u);
  for (const ChunkPart& part : stream.parts) EXPECT_LE(part.data().size(), kChunkPartBytes);
  ChunkRef received;
  EXPECT_EQ(receiveChunk(stream, received, size_t{64 << 20}), bytes);

  // One flipped byte, a missing part, an oversized announcement: all refused.
  PartStream flipped = stream;
  flipped.next = 0;
  flipped.parts[2].mutable_data()->at(10) ^= 1;
  EXPECT_THROW(receiveChunk(flipped, received, size_t{64 << 20}), ChunkError);
  PartStream shortened = stream;
  shortened.next = 0;
  shortened.parts.pop_back();
  EXPECT_THROW(receiveChunk(shortened, received, size_t{64 << 20}), ChunkError);
  stream.next = 0;
  EXPECT_THROW(receiveChunk(stream, received, 1000), ChunkError);
}

}  // namespace
}  // namespace pathfarm::farm
