#include "image/plane_memory.h"

#include <gtest/gtest.h>
#include <sys/resource.h>

#include <cstddef>
#include <memory>
#include <vector>

#include "image/frame_image.h"

namespace pathfarm {
namespace {

long minorPageFaults() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_minflt;
}

// The page faults of building (and dropping) a 40-channel 640x360 frame: 37 MB of planes.
long faultsOfOneFrame() {
  const long before = minorPageFaults();
  {
    auto frame = std::make_unique<FrameImage>(640, 360);
    for (int c = 0; c < 40; ++c) frame->addChannel("layer" + std::to_string(c) + ".Y")[0] = 1.0f;
  }
  return minorPageFaults() - before;
}

TEST(PlaneMemory, AFreedFramesPlanesAreReusedWithoutFreshPageFaults) {
  ASSERT_TRUE(keepFreedPlanesForReuse());
  const long pages = 40L * 640 * 360 * static_cast<long>(sizeof(float)) / 4096;
  faultsOfOneFrame();  // the heap grows once
  // glibc's defaults map each plane afresh and unmap it when freed: every page faults again.
  // Kept for reuse, the second frame's planes land on pages already mapped.
  EXPECT_LT(faultsOfOneFrame(), pages / 20);
}

}  // namespace
}  // namespace pathfarm
