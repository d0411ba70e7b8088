#include "postproc/filters/decomposed_frame.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace pathfarm {
namespace {

// A 2x1 frame of two components, without the channel `missing`.
FrameImage twoComponentFrame(const std::string& missing = "") {
  FrameImage frame(2, 1);
  frame.attributes()["pathfarm.decomposition"] = "diffuse=ED,residual";
  for (const std::string component : {"diffuse", "residual"})
    for (const char* c : {"R", "G", "B"}) {
      frame.addChannel(component + ".color." + c) = {0.6f, 0.2f};
      if (component + ".reflectance." + c != missing)
        frame.addChannel(component + ".reflectance." + c) = {0.5f, 0.0f};  // the second: no reflectance
      frame.addChannel(component + ".irradiance." + c) = {-7.0f, -7.0f};   // stale
    }
  return frame;
}

TEST(DecomposedFrame, IrradianceIsDerivedFromEveryComponentsColorAndReflectance) {
  FrameImage frame = twoComponentFrame();
  frame.channel("residual.color.G") = {0.9f, 0.3f};
  deriveIrradiance(frame);
  // color / reflectance, and the color itself where there is no reflectance to divide by.
  EXPECT_FLOAT_EQ(frame.channel("diffuse.irradiance.R")[0], 1.2f);
  EXPECT_FLOAT_EQ(frame.channel("diffuse.irradiance.B")[1], 0.2f);
  EXPECT_FLOAT_EQ(frame.channel("residual.irradiance.G")[0], 1.8f);
  EXPECT_FLOAT_EQ(frame.channel("residual.irradiance.G")[1], 0.3f);
}

TEST(DecomposedFrame, DerivingIrradianceNamesAMissingChannel) {
  FrameImage frame = twoComponentFrame("residual.reflectance.B");
  try {
    deriveIrradiance(frame);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("residual.reflectance.B"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace pathfarm
