#include "worker/direct_emission.h"

#include <gtest/gtest.h>

namespace pathfarm::farm {
namespace {

// Three components. Pixel 0 sees a light of 4 fully, pixel 1 half covers it (2) and has 1
// of other residual light, pixel 2 sees no light; the mirror component sees the sky (0.5)
// in pixel 2 only; the diffuse component (ED) has no directly seen light at all.
FrameImage frame() {
  FrameImage f(3, 1);
  f.attributes()["pathfarm.decomposition"] = "diffuse=ED,mirror=ER,residual";
  for (const char* c : {"R", "G", "B"}) {
    const std::string n = c;
    f.addChannel(n) = {4.5f, 3.5f, 1.0f};
    f.addChannel("diffuse.color." + n) = {0.5f, 0.5f, 0.5f};
    f.addChannel("diffuse.emission." + n) = {0.0f, 0.0f, 0.0f};
    f.addChannel("diffuse.reflectance." + n) = {0.5f, 0.5f, 0.5f};
    f.addChannel("diffuse.irradiance." + n) = {1.0f, 1.0f, 1.0f};
    f.addChannel("mirror.color." + n) = {0.0f, 0.0f, 0.5f};
    f.addChannel("mirror.emission." + n) = {0.0f, 0.0f, 0.5f};
    f.addChannel("mirror.reflectance." + n) = {0.0f, 0.0f, 0.0f};
    f.addChannel("mirror.irradiance." + n) = {0.0f, 0.0f, 0.5f};
    f.addChannel("residual.color." + n) = {4.0f, 3.0f, 0.0f};
    f.addChannel("residual.emission." + n) = {4.0f, 2.0f, 0.0f};
    f.addChannel("residual.reflectance." + n) = {0.8f, 0.5f, 0.0f};
    f.addChannel("residual.irradiance." + n) = {5.0f, 6.0f, 0.0f};
  }
  return f;
}

TEST(DirectEmission, LeavesEveryComponentAndComesBackExactly) {
  const FrameImage original = frame();
  FrameImage f = original;
  const FrameImage light = takeDirectEmission(f);
  EXPECT_EQ(light.channel("residual.direct.G"), (std::vector<float>{4.0f, 2.0f, 0.0f}));
  EXPECT_EQ(light.channel("mirror.direct.G"), (std::vector<float>{0.0f, 0.0f, 0.5f}));
  EXPECT_FALSE(light.hasChannel("diffuse.direct.G"));  // nothing to carry
  EXPECT_EQ(f.channel("diffuse.color.G"), original.channel("diffuse.color.G"));
  EXPECT_EQ(f.channel("residual.color.G"), (std::vector<float>{0.0f, 1.0f, 0.0f}));
  EXPECT_EQ(f.channel("residual.irradiance.G"), (std::vector<float>{0.0f, 2.0f, 0.0f}));  // 1 / 0.5
  EXPECT_EQ(f.channel("mirror.color.G"), (std::vector<float>{0.0f, 0.0f, 0.0f}));
  EXPECT_EQ(f.channel("G"), (std::vector<float>{0.5f, 1.5f, 0.5f}));
  addDirectEmission(f, light);
  // The original irradiance is color / reflectance (the color where the reflectance is 0),
  // as the renderer derives it, so everything comes back.
  for (const std::string& name : original.channelNames())
    for (size_t p = 0; p < 3; ++p) EXPECT_FLOAT_EQ(f.channel(name)[p], original.channel(name)[p]) << name << " " << p;
}

TEST(DirectEmission, ComesBackWhereAskedOnAFrameWithColorsOnly) {
  FrameImage source = frame();
  const FrameImage light = takeDirectEmission(source);
  // An interpolated frame has the beauty and the components' colors, no irradiance.
  FrameImage f(3, 1);
  f.attributes() = source.attributes();
  for (const std::string& name : {"R", "G", "B", "diffuse.color.R", "diffuse.color.G", "diffuse.color.B",
                                  "mirror.color.R", "mirror.color.G", "mirror.color.B", "residual.color.R",
                                  "residual.color.G", "residual.color.B"})
    f.addChannel(name) = {0.0f, 0.0f, 0.0f};
  const std::vector<uint8_t> only = {1, 0, 1};
  addDirectEmission(f, light, &only);
  EXPECT_EQ(f.channel("G"), (std::vector<float>{4.0f, 0.0f, 0.5f}));
  EXPECT_EQ(f.channel("residual.color.G"), (std::vector<float>{4.0f, 0.0f, 0.0f}));
  EXPECT_EQ(f.channel("mirror.color.G"), (std::vector<float>{0.0f, 0.0f, 0.5f}));
}

TEST(DirectEmission, RefusesAFrameWithoutDecomposition) {
  FrameImage f(1, 1);
  EXPECT_THROW(takeDirectEmission(f), std::invalid_argument);
}

}  // namespace
}  // namespace pathfarm::farm
