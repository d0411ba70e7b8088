#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <fstream>
#include <iterator>

#include "proto/wire/chunk_store.h"
#include "proto/wire/chunk_transfer.h"
#include "test_support.h"

namespace pathfarm::farm {
namespace {

std::filesystem::path freshFolder(const std::string& name) {
  const auto folder = test_support::processTemporaryFolder("pathfarm_chunks") / name;
  std::filesystem::remove_all(folder);
  return folder;
}

TEST(Sha256, MatchesKnownDigests) {
  EXPECT_EQ(sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  Sha256 pieces;
  for (const char* piece : {"a", "", "bc"}) pieces.update(piece);
  EXPECT_EQ(pieces.hex(), sha256Hex("abc"));
}

// Files under `folder` whose name ends in .partial: temporaries left behind.
size_t partialFiles(const std::filesystem::path& folder) {
  size_t count = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(folder))
    count += entry.path().extension() == ".partial" ? 1 : 0;
  return count;
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

// A writer killed mid-chunk (a scheduler or worker host that lost power) leaves its
// temporary; the next start removes it, and leaves those of writers still running.
TEST(ChunkStore, TheTemporariesOfKilledWritersAreRemovedAndThoseOfLiveOnesKept) {
  const auto folder = freshFolder("abandoned");
  ChunkStore store(folder);
  const ChunkRef kept = store.put("a whole chunk");
  const std::string bytes = "a chunk its writer never finished";
  const auto target = folder / "objects" / sha256Hex(bytes).substr(0, 2) / sha256Hex(bytes).substr(2);
  std::filesystem::create_directories(target.parent_path());
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    AtomicFileWriter killed(target);
    killed.append(bytes.substr(0, 8));
    raise(SIGKILL);
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFSIGNALED(status));
  AtomicFileWriter running(target);  // this process's: still running
  running.append(bytes);
  ASSERT_EQ(partialFiles(folder), 2u);

  EXPECT_EQ(store.removeAbandonedWrites(), 1u);
  EXPECT_EQ(partialFiles(folder), 1u);
  running.commit();
  EXPECT_EQ(store.get(sha256Hex(bytes)).value(), bytes);
  EXPECT_EQ(store.get(kept.sha256()).value(), "a whole chunk");
  EXPECT_EQ(partialFiles(folder), 0u);
  EXPECT_EQ(store.removeAbandonedWrites(), 0u);
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

TEST(ChunkTransfer, AStreamGoesToDiskAndBackInPartsAndOnlyWholeMatchingChunksAreStored) {
  const auto folder = freshFolder("streamed");
  ChunkStore store(folder);
  std::string bytes(2 * kChunkPartBytes + 5, '\0');
  for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<char>(i * 31 % 253);
  ChunkRef ref;
  ref.set_sha256(sha256Hex(bytes));
  ref.set_size(static_cast<int64_t>(bytes.size()));
  PartStream incoming;
  ASSERT_TRUE(sendChunk(incoming, ref, bytes));

  // Damaged on the way or cut short: nothing stored, no temporary left.
  PartStream flipped = incoming;
  flipped.parts[1].mutable_data()->at(0) ^= 1;
  EXPECT_THROW(receiveChunkIntoStore(flipped, store, size_t{64 << 20}), ChunkError);
  PartStream shortened = incoming;
  shortened.parts.pop_back();
  EXPECT_THROW(receiveChunkIntoStore(shortened, store, size_t{64 << 20}), ChunkError);
  EXPECT_THROW(receiveChunkIntoStore(incoming, store, 1000), ChunkError);
  incoming.next = 0;
  EXPECT_FALSE(store.has(ref.sha256()));
  EXPECT_EQ(partialFiles(folder), 0u);

  EXPECT_EQ(receiveChunkIntoStore(incoming, store, size_t{64 << 20}).sha256(), ref.sha256());
  EXPECT_EQ(store.get(ref.sha256()).value(), bytes);
  incoming.next = 0;
  EXPECT_EQ(receiveChunkIntoStore(incoming, store, size_t{64 << 20}).size(), ref.size()) << "stored twice";

  // Out again in bounded parts, the same bytes.
  PartStream outgoing;
  ASSERT_EQ(sendStoredChunk(outgoing, store, ref.sha256()), StoredSend::Sent);
  EXPECT_EQ(outgoing.parts.size(), 3u);
  for (const ChunkPart& part : outgoing.parts) EXPECT_LE(part.data().size(), kChunkPartBytes);
  ChunkRef received;
  EXPECT_EQ(receiveChunk(outgoing, received, size_t{64 << 20}), bytes);

  // A file damaged on disk is not sent, and is removed.
  const std::string damaged(bytes.size(), 'x');
  for (const auto& entry : std::filesystem::recursive_directory_iterator(folder))
    if (entry.is_regular_file()) std::ofstream(entry.path(), std::ios::binary) << damaged;
  PartStream none;
  EXPECT_EQ(sendStoredChunk(none, store, ref.sha256()), StoredSend::Absent);
  EXPECT_TRUE(none.parts.empty());
  EXPECT_FALSE(store.has(ref.sha256()));
  std::filesystem::remove_all(folder);
}

TEST(ChunkTransfer, AnEmptyChunkIsOneEmptyPart) {
  const auto folder = freshFolder("empty");
  ChunkStore store(folder);
  const ChunkRef ref = store.put("");
  PartStream outgoing;
  ASSERT_EQ(sendStoredChunk(outgoing, store, ref.sha256()), StoredSend::Sent);
  ASSERT_EQ(outgoing.parts.size(), 1u);
  EXPECT_EQ(outgoing.parts[0].ref().sha256(), ref.sha256());
  outgoing.next = 0;
  EXPECT_EQ(receiveChunkIntoStore(outgoing, store, 10).size(), 0);
  std::filesystem::remove_all(folder);
}

// An output leaves a file on the worker (an assembled frame) and arrives in a file on the
// client (a fetched frame): neither end holds it whole, and the client's file appears only
// when the whole chunk checks out.
TEST(ChunkTransfer, AFileTravelsInPartsIntoAFileThatAppearsOnlyWhenItChecksOut) {
  const auto folder = freshFolder("files");
  std::filesystem::create_directories(folder);
  std::string bytes(2 * kChunkPartBytes + 77, '\0');
  for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<char>(i * 13 % 241);
  std::ofstream(folder / "frame.exr", std::ios::binary) << bytes;
  const ChunkRef ref = refOfFile(folder / "frame.exr");
  EXPECT_EQ(ref.sha256(), sha256Hex(bytes));
  EXPECT_EQ(ref.size(), static_cast<int64_t>(bytes.size()));
  EXPECT_THROW(refOfFile(folder / "absent.exr"), ChunkError);
  PartStream stream;
  ASSERT_TRUE(sendFileChunk(stream, ref, folder / "frame.exr"));
  ASSERT_EQ(stream.parts.size(), 3u);
  for (const ChunkPart& part : stream.parts) EXPECT_LE(part.data().size(), kChunkPartBytes);

  const auto receive = [&](const PartStream& parts, const std::filesystem::path& file) {
    IncomingChunk chunk(parts.parts[0].ref(), size_t{64 << 20}, file, AtomicFileWriter::Sync::No, "write frame");
    for (const ChunkPart& part : parts.parts) chunk.append(part.data());
    return chunk.commit();
  };
  PartStream flipped = stream;
  flipped.parts[2].mutable_data()->at(5) ^= 1;
  EXPECT_THROW(receive(flipped, folder / "out" / "flipped.exr"), ChunkError);
  EXPECT_FALSE(std::filesystem::exists(folder / "out" / "flipped.exr"));
  EXPECT_EQ(partialFiles(folder), 0u);
  EXPECT_EQ(receive(stream, folder / "out" / "frame.exr").sha256(), ref.sha256());
  std::ifstream in(folder / "out" / "frame.exr", std::ios::binary);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), bytes);
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace pathfarm::farm
