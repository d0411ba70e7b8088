#include "postproc/filters/direct_emission.h"

#include <gtest/gtest.h>

namespace pathfarm {
namespace {

// Three components. Pixel 0 sees a light of 4 fully, pixel 1 half covers it (2) and has 1
// of other residual light, pixel 2 sees no light; the mirror component sees the sky (0.5)
// in pixel 2 only; the diffuse component (ED) has no directly seen light at all.
FrameImage frame() {
  using Plane = std::vector<float>;
  FrameImage f(3, 1);
  f.attributes()["pathfarm.decomposition"] = "diffuse=ED,mirror=ER,residual";
  // Each buffer the same in R, G and B.
  const auto add = [&](const std::string& component, const Plane& color, const Plane& emission,
                       const Plane& reflectance, const Plane& irradiance) {
    for (const char* c : {"R", "G", "B"}) {
      f.addChannel(component + ".color." + c) = color;
      f.addChannel(component + ".emission." + c) = emission;
      f.addChannel(component + ".reflectance." + c) = reflectance;
      f.addChannel(component + ".irradiance." + c) = irradiance;
    }
  };
  for (const char* c : {"R", "G", "B"}) f.addChannel(c) = {4.5f, 3.5f, 1.0f};
  add("diffuse", {0.5f, 0.5f, 0.5f}, {0.0f, 0.0f, 0.0f}, {0.5f, 0.5f, 0.5f}, {1.0f, 1.0f, 1.0f});
  add("mirror", {0.0f, 0.0f, 0.5f}, {0.0f, 0.0f, 0.5f}, {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.5f});
  add("residual", {4.0f, 3.0f, 0.0f}, {4.0f, 2.0f, 0.0f}, {0.8f, 0.5f, 0.0f}, {5.0f, 6.0f, 0.0f});
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

TEST(DirectEmission, ItsLightCanBeReadWithoutTakingIt) {
  const FrameImage original = frame();
  const FrameImage read = directEmissionOf(original);
  FrameImage taken = original;
  const FrameImage light = takeDirectEmission(taken);
  ASSERT_EQ(read.channelNames(), light.channelNames());
  for (const std::string& name : light.channelNames()) EXPECT_EQ(read.channel(name), light.channel(name)) << name;
  EXPECT_EQ(read.channel("residual.direct.R"), (std::vector<float>{4.0f, 2.0f, 0.0f}));
}

TEST(DirectEmission, ComesBackWhereAskedOnAFrameWithColorsOnly) {
  FrameImage source = frame();
  const FrameImage light = takeDirectEmission(source);
  // An interpolated frame has the beauty and the components' colors, no irradiance.
  FrameImage f(3, 1);
  f.attributes() = source.attributes();
  for (const char* name : {"R", "G", "B", "diffuse.color.R", "diffuse.color.G", "diffuse.color.B",
                                  "mirror.color.R", "mirror.color.G", "mirror.color.B", "residual.color.R",
                                  "residual.color.G", "residual.color.B"})
    f.addChannel(name) = {0.0f, 0.0f, 0.0f};
  const std::vector<uint8_t> only = {1, 0, 1};
  addDirectEmission(f, light, &only);
  EXPECT_EQ(f.channel("G"), (std::vector<float>{4.0f, 0.0f, 0.5f}));
  EXPECT_EQ(f.channel("residual.color.G"), (std::vector<float>{4.0f, 0.0f, 0.0f}));
  EXPECT_EQ(f.channel("mirror.color.G"), (std::vector<float>{0.0f, 0.0f, 0.5f}));
}

// A 6x3 frame: the residual sees a lamp of 10 in columns 0-2 (column 2 half covered, read
// as 10 by few samples), a dim wall of 0.2 elsewhere.
TEST(DirectEmission, EdgesOfTheLightAreFlaggedOnBothSides) {
  FrameImage f(6, 3);
  f.attributes()["pathfarm.decomposition"] = "diffuse=ED,residual";
  const std::vector<float> row = {10, 10, 10, 0, 0, 0};
  const std::vector<float> beautyRow = {10, 10, 10, 0.2f, 0.2f, 0.2f};
  for (const char* c : {"R", "G", "B"}) {
    const std::string n = c;
    std::vector<float> light, beauty;
    for (int y = 0; y < 3; ++y) {
      light.insert(light.end(), row.begin(), row.end());
      beauty.insert(beauty.end(), beautyRow.begin(), beautyRow.end());
    }
    f.addChannel(n) = beauty;
    f.addChannel("residual.color." + n) = beauty;
    f.addChannel("residual.emission." + n) = light;
    f.addChannel("diffuse.color." + n) = std::vector<float>(18, 0.0f);
    f.addChannel("diffuse.emission." + n) = std::vector<float>(18, 0.0f);
  }
  FrameImage taken = f;
  const FrameImage light = takeDirectEmission(taken);
  const std::vector<uint8_t> edges = directLightEdges(light, f);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 6; ++x)
      EXPECT_EQ(edges[static_cast<size_t>(y * 6 + x)], x == 2 || x == 3 ? 1 : 0) << x << "," << y;
  // A light that changes by less than the significance is no edge.
  for (const char* c : {"R", "G", "B"}) {
    std::vector<float>& direct = f.channel(std::string("residual.emission.") + c);
    for (size_t p = 0; p < direct.size(); ++p) direct[p] = direct[p] > 0 ? 10.0f + 0.01f * static_cast<float>(p % 6) : 0.0f;
  }
  taken = f;
  const std::vector<uint8_t> gentle = directLightEdges(takeDirectEmission(taken), f);
  EXPECT_EQ(gentle[1], 0);
  EXPECT_EQ(gentle[2], 1);
}

TEST(DirectEmission, RefusesAFrameWithoutDecomposition) {
  FrameImage f(1, 1);
  EXPECT_THROW(takeDirectEmission(f), std::invalid_argument);
}

}  // namespace
}  // namespace pathfarm
