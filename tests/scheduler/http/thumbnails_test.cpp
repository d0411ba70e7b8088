// The dashboard's thumbnails: block means of the beauty, read from the frame's file a strip
// at a time, equal the means taken over the whole decoded frame.
#include "scheduler/http/thumbnails.h"

#include <gtest/gtest.h>

#include <fstream>

#include "image/exr_io.h"
#include "test_support.h"

namespace pathfarm::farm {
namespace {

TEST(Thumbnails, BlockMeansOfAFrameReadInStripsEqualThoseOfTheWholeFrame) {
  // 70 x 37 in blocks of 4 (the longest edge over 20): 18 x 10, the last column of blocks
  // 2 pixels wide and the last row 1 pixel high. 37 rows are more than two strips.
  FrameImage frame(70, 37);
  for (const char* name : {"R", "G", "B", "depth.Z"}) {
    std::vector<float>& plane = frame.addChannel(name);
    for (size_t p = 0; p < plane.size(); ++p) plane[p] = static_cast<float>((p * 7919 + name[0]) % 1000) / 100.0f;
  }
  const std::filesystem::path file = test_support::processTemporaryFolder("pathfarm_thumbnails") / "frame.exr";
  std::ofstream(file, std::ios::binary | std::ios::trunc) << encodeExr(frame);
  const FrameImage small = shrinkBeauty(file, "frame", 20);
  ASSERT_EQ(small.width(), 18);
  ASSERT_EQ(small.height(), 10);
  EXPECT_FALSE(small.hasChannel("depth.Z"));
  for (const char* name : {"R", "G", "B"})
    for (int y = 0; y < 10; ++y)
      for (int x = 0; x < 18; ++x) {
        double sum = 0;
        int count = 0;
        for (int v = 4 * y; v < std::min(37, 4 * y + 4); ++v)
          for (int u = 4 * x; u < std::min(70, 4 * x + 4); ++u, ++count)
            sum += frame.channel(name)[static_cast<size_t>(v) * 70 + static_cast<size_t>(u)];
        EXPECT_NEAR(small.channel(name)[static_cast<size_t>(y) * 18 + static_cast<size_t>(x)], sum / count, 1e-5)
            << name << " block (" << x << ", " << y << ")";
      }
  // A frame that fits comes out as it is; a file without a beauty is refused by name.
  const FrameImage same = shrinkBeauty(file, "frame", 100);
  EXPECT_EQ(same.channel("G"), frame.channel("G"));
  FrameImage depthOnly(4, 4);
  depthOnly.addChannel("depth.Z");
  std::ofstream(file, std::ios::binary | std::ios::trunc) << encodeExr(depthOnly);
  EXPECT_THROW(shrinkBeauty(file, "frame", 20), ExrError);
}

}  // namespace
}  // namespace pathfarm::farm
