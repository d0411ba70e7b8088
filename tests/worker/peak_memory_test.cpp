// The worker's per-task peak memory: restarting the count forgets an earlier, larger peak,
// and a block touched after the restart shows in the peak.
#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <vector>

#include "image/plane_memory.h"
#include "worker/peak_memory.h"

namespace pathfarm::farm {
namespace {

constexpr size_t kBlock = size_t{256} << 20;

// Allocates and touches `bytes`, then frees them.
void touchAndFree(size_t bytes) {
  const std::unique_ptr<char[]> block(new char[bytes]);
  std::memset(block.get(), 1, bytes);
  volatile char sink = block[bytes - 1];
  (void)sink;
}

TEST(PeakMemory, ARestartForgetsAnEarlierPeakAndSeesALaterOne) {
  if (!restartPeakResident()) GTEST_SKIP() << "this kernel does not let a process restart its peak (clear_refs)";
  const std::optional<uint64_t> idle = peakResidentBytes();
  ASSERT_TRUE(idle);
  touchAndFree(kBlock);
  const std::optional<uint64_t> afterBlock = peakResidentBytes();
  ASSERT_TRUE(afterBlock);
  EXPECT_GE(*afterBlock, *idle + kBlock * 9 / 10);
  ASSERT_TRUE(restartPeakResident());
  const std::optional<uint64_t> restarted = peakResidentBytes();
  ASSERT_TRUE(restarted);
  EXPECT_LT(*restarted, *afterBlock - kBlock / 2) << "the freed block still counts after the restart";
}

// Memory a task freed in small blocks stays in the heap (below a block still in use, the
// heap cannot shrink): what is more than the 512 MB kept for reuse is given back before the
// next task, or its peak would start there.
TEST(PeakMemory, FreedHeapBeyondWhatIsKeptForReuseIsGivenBack) {
  if (!restartPeakResident()) GTEST_SKIP() << "this kernel does not let a process restart its peak (clear_refs)";
  keepFreedPlanesForReuse();  // as the worker's process does
  constexpr size_t kSmall = size_t{64} << 10;  // below malloc's mmap threshold: from the heap
  std::vector<std::unique_ptr<char[]>> blocks;
  for (size_t i = 0; i < 5 * kBlock / 2 / kSmall; ++i) {  // 640 MB
    blocks.emplace_back(new char[kSmall]);
    std::memset(blocks.back().get(), 1, kSmall);
  }
  const std::unique_ptr<char[]> pin(new char[kSmall]);  // above them, in use
  std::memset(pin.get(), 1, kSmall);
  const std::optional<uint64_t> afterBlocks = peakResidentBytes();
  ASSERT_TRUE(afterBlocks);
  blocks.clear();
  returnFreedBeyondReuse();
  ASSERT_TRUE(restartPeakResident());
  const std::optional<uint64_t> restarted = peakResidentBytes();
  ASSERT_TRUE(restarted);
  EXPECT_LT(*restarted, *afterBlocks - kBlock / 2) << "the heap kept the freed blocks";
}

}  // namespace
}  // namespace pathfarm::farm
