#include "worker/direct_emission.h"

#include <gtest/gtest.h>

namespace pathfarm::farm {
namespace {

// Two components; pixel 0 sees a light of 4 fully, pixel 1 half covers it (emission 2) and
// has 1 of other residual light, pixel 2 sees no light.
FrameImage frame() {
  FrameImage f(3, 1);
  f.attributes()["pathfarm.decomposition"] = "diffuse=ED,residual";
  for (const char* c : {"R", "G", "B"}) {
    const std::string n = c;
    f.addChannel(n) = {4.5f, 3.5f, 0.5f};
    f.addChannel("diffuse.color." + n) = {0.5f, 0.5f, 0.5f};
    f.addChannel("diffuse.emission." + n) = {4.0f, 2.0f, 0.0f};
    f.addChannel("diffuse.reflectance." + n) = {0.5f, 0.5f, 0.5f};
    f.addChannel("diffuse.irradiance." + n) = {1.0f, 1.0f, 1.0f};
    f.addChannel("residual.color." + n) = {4.0f, 3.0f, 0.0f};
    f.addChannel("residual.emission." + n) = {4.0f, 2.0f, 0.0f};
    f.addChannel("residual.reflectance." + n) = {0.8f, 0.5f, 0.0f};
    f.addChannel("residual.irradiance." + n) = {5.0f, 6.0f, 0.0f};
  }
  return f;
}

TEST(DirectEmission, LeavesTheReceivingComponentAndComesBackExactly) {
  const FrameImage original = frame();
  FrameImage f = original;
  const FrameImage light = takeDirectEmission(f);
  EXPECT_EQ(light.channel("direct_emission.G"), (std::vector<float>{4.0f, 2.0f, 0.0f}));
  // Zero-bounce emission goes to the residual: the diffuse component (ED) keeps its color.
  EXPECT_EQ(f.channel("diffuse.color.G"), original.channel("diffuse.color.G"));
  EXPECT_EQ(f.channel("residual.color.G"), (std::vector<float>{0.0f, 1.0f, 0.0f}));
  EXPECT_EQ(f.channel("residual.irradiance.G"), (std::vector<float>{0.0f, 2.0f, 0.0f}));  // 1 / 0.5
  EXPECT_EQ(f.channel("G"), (std::vector<float>{0.5f, 1.5f, 0.5f}));
  addDirectEmission(f, light);
  // The original irradiance is color / reflectance (the color where the reflectance is 0),
  // as the renderer derives it, so everything comes back.
  for (const std::string& name : original.channelNames())
    for (size_t p = 0; p < 3; ++p) EXPECT_FLOAT_EQ(f.channel(name)[p], original.channel(name)[p]) << name << " " << p;
}

TEST(DirectEmission, RefusesAFrameWithoutDecomposition) {
  FrameImage f(1, 1);
  EXPECT_THROW(takeDirectEmission(f), std::invalid_argument);
}

}  // namespace
}  // namespace pathfarm::farm
