#include "postproc/interpolation/feature_check.h"

#include <gtest/gtest.h>

namespace pathfarm {
namespace {

// Five pixels of one component "c" (gray colors: luminance = the value).
FrameImage frame(const std::vector<float>& color, const std::vector<float>& beauty) {
  FrameImage f(5, 1);
  f.attributes()["pathfarm.decomposition"] = "c=ED,residual";
  for (const char* ch : {"R", "G", "B"}) {
    f.addChannel(ch) = beauty;
    f.addChannel(std::string("c.color.") + ch) = color;
    f.addChannel(std::string("residual.color.") + ch) = std::vector<float>(5, 0.0f);
  }
  return f;
}

TEST(FeatureCheck, FlagsWrongDepthsAndSignificantComponentsOnOneSideOnly) {
  FrameImage interpolated = frame({1, 1, 0, 1, 0}, {1, 1, 1, 1, 1});
  interpolated.addChannel("c.depth.Z") = {2.0f, 2.0f, 0.0f, 3.0f, 0.0f};
  interpolated.addChannel("residual.depth.Z") = std::vector<float>(5, 0.0f);
  FrameImage features = frame({1, 1, 1, 0, 0.001f}, {1, 1, 1, 1, 1});
  features.addChannel("c.depth.Z") = {2.05f, 2.5f, 2.0f, 0.0f, 2.0f};
  features.addChannel("c.normal.X") = {0, 0, 0, 0, 0};
  features.addChannel("c.normal.Y") = {1, 1, 1, 0, 1};
  features.addChannel("c.normal.Z") = {0, 0, 0, 0, 0};
  for (const char* axis : {"X", "Y", "Z"}) features.addChannel(std::string("residual.normal.") + axis);
  features.addChannel("residual.depth.Z");
  // 0: depths within 5 %; 1: 25 % apart; 2: really there but not interpolated; 3: interpolated
  // but not really there; 4: really there, but too faint to matter.
  EXPECT_EQ(featureMismatch(interpolated, features), (std::vector<uint8_t>{0, 1, 1, 1, 0}));
}

TEST(FeatureCheck, RefusesMismatchedFrames) {
  FrameImage interpolated = frame({1, 1, 1, 1, 1}, {1, 1, 1, 1, 1});
  interpolated.addChannel("c.depth.Z");
  interpolated.addChannel("residual.depth.Z");
  EXPECT_THROW(featureMismatch(interpolated, FrameImage(4, 1)), std::invalid_argument);
  try {
    featureMismatch(interpolated, frame({1, 1, 1, 1, 1}, {1, 1, 1, 1, 1}));
    FAIL() << "no error for features without depth";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("\"c.depth.Z\""), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pathfarm
