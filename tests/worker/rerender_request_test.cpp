// The sparse re-render an upsample or interpolate task asks for (worker/filter_inputs.h,
// requestRerender): a render task per tile holding a flagged pixel, rendering just those.
#include <gtest/gtest.h>

#include <numeric>

#include "worker/failure_class.h"
#include "worker/filter_inputs.h"

namespace pathfarm::farm {
namespace {

constexpr int kMaskWidth = 40, kMaskHeight = 24, kMaskTile = 16;  // tiles of 16, 16 and 8 columns, 16 and 8 rows

ShotSpec rerenderShot(Pipeline pipeline, int rerenderSpp) {
  ShotSpec spec;
  spec.set_width(kMaskWidth);
  spec.set_height(kMaskHeight);
  spec.set_tile(kMaskTile);
  spec.set_spp(256);
  spec.set_pipeline(pipeline);
  spec.set_rerender_spp(rerenderSpp);
  return spec;
}

TEST(RerenderRequest, EachTileWithAFlaggedPixelRendersThoseAtTheShotsRerenderSpp) {
  std::vector<uint8_t> mask(kMaskWidth * kMaskHeight, 0);
  mask[3 * kMaskWidth + 5] = 1;                             // tile (0, 0)
  mask[20 * kMaskWidth + 35] = mask[23 * kMaskWidth + 39] = 1;  // tile (32, 16), the corner's
  TaskOutput output;
  requestRerender(rerenderShot(PIPELINE_DUI, 128), 7, mask, output);
  ASSERT_EQ(output.followUps.size(), 2u);
  EXPECT_EQ(output.metrics.at("rerender_pixels"), 3.0);
  EXPECT_EQ(output.metrics.at("pixels"), static_cast<double>(kMaskWidth * kMaskHeight));
  const TaskParams& first = output.followUps[0];
  const TaskParams& corner = output.followUps[1];
  EXPECT_EQ(first.role(), ROLE_RERENDER);
  EXPECT_EQ(first.frame(), 7);
  EXPECT_EQ(first.spp(), 128);  // the shot's rerender_spp
  EXPECT_EQ(corner.spp(), 128);
  EXPECT_EQ(corner.window().x0(), 32);
  EXPECT_EQ(corner.window().y0(), 16);
  EXPECT_EQ(corner.window().x1(), kMaskWidth);
  EXPECT_EQ(corner.window().y1(), kMaskHeight);
  // The corner tile is 8 x 8; its flags at (3, 4) and (7, 7) of it.
  ASSERT_EQ(corner.pixel_mask().size(), 64u);
  EXPECT_EQ(std::accumulate(corner.pixel_mask().begin(), corner.pixel_mask().end(), 0), 2);
  EXPECT_EQ(corner.pixel_mask()[4 * 8 + 3], 1);
  EXPECT_EQ(corner.pixel_mask()[7 * 8 + 7], 1);

  TaskOutput given, full;
  requestRerender(rerenderShot(PIPELINE_DUI, 1000), 7, mask, given);
  requestRerender(rerenderShot(PIPELINE_DUI, 0), 7, mask, full);
  EXPECT_EQ(given.followUps[0].spp(), 256);  // at most the shot's spp
  EXPECT_EQ(full.followUps[0].spp(), 256);   // by default the shot's spp
}

TEST(RerenderRequest, NothingFlaggedAsksForNothingAndAMaskOfAnotherSizeIsRefused) {
  TaskOutput output;
  requestRerender(rerenderShot(PIPELINE_DUI, 0), 0, std::vector<uint8_t>(kMaskWidth * kMaskHeight, 0), output);
  EXPECT_TRUE(output.followUps.empty());
  EXPECT_EQ(output.metrics.at("rerender_pixels"), 0.0);
  EXPECT_THROW(requestRerender(rerenderShot(PIPELINE_DUI, 0), 0, std::vector<uint8_t>(kMaskWidth, 1), output), BadInput);
}

}  // namespace
}  // namespace pathfarm::farm
