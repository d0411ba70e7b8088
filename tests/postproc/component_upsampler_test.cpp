#include "postproc/filters/component_upsampler.h"

#include <gtest/gtest.h>

#include "test_support.h"

#include <cmath>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>

#include "renderer/decomposition/effective_irradiance.h"

namespace pathfarm {
namespace {

constexpr int kFactor = 2, kLowWidth = 8, kLowHeight = 6;
constexpr int kFullWidth = kLowWidth * kFactor, kFullHeight = kLowHeight * kFactor;
constexpr const char* kUpsampledChannels[] = {"R", "G", "B"};
constexpr const char* kXyz[] = {"X", "Y", "Z"};
const std::string kDecomposition = "diffuse=ED,residual";
const std::string kComponents[] = {"diffuse", "residual"};

using test_support::hashed;

size_t index(int x, int y, int width) { return static_cast<size_t>(y) * width + x; }

// Component k's full-resolution surface: left of x = 8 one normal, right of it another.
bool rightSide(int x) { return x >= kFullWidth / 2; }

// A textured reflectance; diffuse's pixel (3, 4) is black (below the guard).
float reflectanceOf(int k, int c, int x, int y) {
  if (k == 0 && x == 3 && y == 4) return 0.0f;
  return 0.1f + 0.8f * hashed(static_cast<uint32_t>(10 + k), c, x, y);
}

FrameImage makeHighFeatures() {
  FrameImage high(kFullWidth, kFullHeight);
  high.attributes()["pathfarm.decomposition"] = kDecomposition;
  for (int k = 0; k < 2; ++k) {
    const std::string& name = kComponents[k];
    for (int c = 0; c < 3; ++c) {
      std::vector<float>& reflectance = high.addChannel(name + ".reflectance." + kUpsampledChannels[c]);
      std::vector<float>& normal = high.addChannel(name + ".normal." + kXyz[c]);
      high.addChannel(name + ".emission." + kUpsampledChannels[c]);
      for (int y = 0; y < kFullHeight; ++y)
        for (int x = 0; x < kFullWidth; ++x) {
          reflectance[index(x, y, kFullWidth)] = reflectanceOf(k, c, x, y);
          const float left[3] = {0.0f, 0.0f, 1.0f}, right[3] = {0.6f, 0.0f, 0.8f};
          normal[index(x, y, kFullWidth)] = rightSide(x) ? right[c] : left[c];
        }
    }
  }
  return high;
}

// Component k's low-resolution irradiance from irradiance(k, channel, lowX, lowY).
FrameImage makeLow(const std::function<float(int, int, int, int)>& irradiance) {
  FrameImage low(kLowWidth, kLowHeight);
  low.attributes()["pathfarm.decomposition"] = kDecomposition;
  low.attributes()["pathfarm.spp"] = "16";
  for (int k = 0; k < 2; ++k)
    for (int c = 0; c < 3; ++c) {
      std::vector<float>& plane = low.addChannel(kComponents[k] + ".irradiance." + kUpsampledChannels[c]);
      for (int y = 0; y < kLowHeight; ++y)
        for (int x = 0; x < kLowWidth; ++x) plane[index(x, y, kLowWidth)] = irradiance(k, c, x, y);
    }
  return low;
}

UpsampleSettings settingsOf(float epsilon) {
  UpsampleSettings settings;
  settings.guided.factor = kFactor;
  settings.guided.radius = 2;
  settings.guided.epsilon = epsilon;
  return settings;
}

TEST(ComponentUpsampler, ModulatesTheUpsampledIrradianceAndSumsTheComponents) {
  const float irradiance[2][3] = {{0.8f, 0.5f, 0.2f}, {0.1f, 0.2f, 0.3f}};
  const FrameImage low = makeLow([&](int k, int c, int, int) { return irradiance[k][c]; });
  const FrameImage high = makeHighFeatures();
  const FrameImage out = upsampleFrame(low, high, settingsOf(1e-3f));

  ASSERT_EQ(out.width(), kFullWidth);
  ASSERT_EQ(out.height(), kFullHeight);
  EXPECT_EQ(out.attributes().at("pathfarm.rerender_pixels"), "0");
  EXPECT_EQ(out.attributes().at("pathfarm.spp"), "16");  // the low frame's attributes
  EXPECT_EQ(out.attributes().at("pathfarm.decomposition"), kDecomposition);
  EXPECT_NE(out.attributes().at("pathfarm.upsample").find("factor=2"), std::string::npos);
  for (const float flag : out.channel("rerender.Y")) EXPECT_EQ(flag, 0.0f);
  for (int c = 0; c < 3; ++c)
    for (int y = 0; y < kFullHeight; ++y)
      for (int x = 0; x < kFullWidth; ++x) {
        const size_t i = index(x, y, kFullWidth);
        float sum = 0;
        for (int k = 0; k < 2; ++k) {
          const std::string& name = kComponents[k];
          const float up = out.channel(name + ".irradiance." + kUpsampledChannels[c])[i];
          EXPECT_NEAR(up, irradiance[k][c], 1e-6f);
          const float reflectance = reflectanceOf(k, c, x, y);
          const float color = out.channel(name + ".color." + kUpsampledChannels[c])[i];
          EXPECT_FLOAT_EQ(color, modulateIrradiance(up, reflectance));
          EXPECT_NEAR(color, reflectance < kReflectanceGuard ? irradiance[k][c] : irradiance[k][c] * reflectance, 1e-6f);
          sum += color;
        }
        EXPECT_FLOAT_EQ(out.channel(kUpsampledChannels[c])[i], sum);
      }
  // Black diffuse reflectance: the irradiance is the color itself.
  EXPECT_NEAR(out.channel("diffuse.color.G")[index(3, 4, kFullWidth)], 0.5f, 1e-6f);
}

TEST(ComponentUpsampler, KeepsAnIlluminationEdgeTheNormalsShare) {
  // Diffuse light changes where the normal does (low-resolution column 4 = x 8); the
  // reflectance texture in the guide must not disturb it.
  const FrameImage low = makeLow([](int k, int c, int x, int) {
    if (k == 1) return 0.05f;
    return x >= kLowWidth / 2 ? 2.0f + 0.5f * c : 0.3f;
  });
  const FrameImage out = upsampleFrame(low, makeHighFeatures(), settingsOf(1e-7f));
  EXPECT_EQ(out.attributes().at("pathfarm.rerender_pixels"), "0");
  for (int c = 0; c < 3; ++c)
    for (int y = 0; y < kFullHeight; ++y)
      for (int x = 0; x < kFullWidth; ++x) {
        const float expected = rightSide(x) ? 2.0f + 0.5f * c : 0.3f;
        ASSERT_NEAR(out.channel(std::string("diffuse.irradiance.") + kUpsampledChannels[c])[index(x, y, kFullWidth)], expected, 1e-4f)
            << "(" << x << ", " << y << ")";
      }
}

TEST(ComponentUpsampler, FlagsAndCountsNegativeResultsFrameWide) {
  // Residual irradiance is -1 in the two left low-resolution columns, 1 elsewhere.
  const FrameImage low = makeLow([](int k, int, int x, int) { return k == 0 ? 0.5f : (x < 2 ? -1.0f : 1.0f); });
  const FrameImage out = upsampleFrame(low, makeHighFeatures(), settingsOf(1e-3f));
  const std::vector<float>& rerender = out.channel("rerender.Y");
  size_t flagged = 0;
  for (int y = 0; y < kFullHeight; ++y)
    for (int x = 0; x < kFullWidth; ++x) {
      const size_t i = index(x, y, kFullWidth);
      flagged += rerender[i] != 0 ? 1 : 0;
      if (x == 0) {
        EXPECT_EQ(rerender[i], 1.0f);
      }
      if (x == kFullWidth - 1) {
        EXPECT_EQ(rerender[i], 0.0f);
      }
      if (rerender[i] != 0) {
        EXPECT_EQ(out.channel("residual.color.R")[i], 0.0f);
        EXPECT_FLOAT_EQ(out.channel("R")[i], out.channel("diffuse.color.R")[i]);
      }
    }
  EXPECT_GT(flagged, 0u);
  EXPECT_EQ(out.attributes().at("pathfarm.rerender_pixels"), std::to_string(flagged));
}

TEST(ComponentUpsampler, BeatsNearestUpsamplingInTheEvaluationProtocol) {
  // A target-resolution "render": smooth light over textured reflectance; its box
  // downsample is the low-resolution input, its features the guide.
  FrameImage target = makeHighFeatures();
  for (int k = 0; k < 2; ++k)
    for (int c = 0; c < 3; ++c) {
      const std::string suffix = std::string(".") + kUpsampledChannels[c];
      std::vector<float>& color = target.addChannel(kComponents[k] + ".color" + suffix);
      std::vector<float>& irradiance = target.addChannel(kComponents[k] + ".irradiance" + suffix);
      const std::vector<float>& reflectance = target.channel(kComponents[k] + ".reflectance" + suffix);
      for (int y = 0; y < kFullHeight; ++y)
        for (int x = 0; x < kFullWidth; ++x) {
          const size_t i = index(x, y, kFullWidth);
          const float light = (k == 0 ? 1.0f : 0.2f) * (1.0f + 0.03f * x + 0.02f * y + 0.1f * c);
          color[i] = light * std::max(reflectance[i], kReflectanceGuard);
          irradiance[i] = effectiveIrradiance(color[i], reflectance[i]);
        }
    }
  for (int c = 0; c < 3; ++c) {
    std::vector<float>& beauty = target.addChannel(kUpsampledChannels[c]);
    for (size_t i = 0; i < beauty.size(); ++i)
      beauty[i] = target.channel(std::string("diffuse.color.") + kUpsampledChannels[c])[i] +
                  target.channel(std::string("residual.color.") + kUpsampledChannels[c])[i];
  }
  const FrameImage low = boxDownsample(target, kFactor);
  const FrameImage out = upsampleFrame(low, target, settingsOf(1e-3f));
  double guidedError = 0, nearestError = 0;
  for (int c = 0; c < 3; ++c)
    for (int y = 0; y < kFullHeight; ++y)
      for (int x = 0; x < kFullWidth; ++x) {
        const float truth = target.channel(kUpsampledChannels[c])[index(x, y, kFullWidth)];
        guidedError += std::abs(out.channel(kUpsampledChannels[c])[index(x, y, kFullWidth)] - truth);
        nearestError += std::abs(low.channel(kUpsampledChannels[c])[index(x / kFactor, y / kFactor, kLowWidth)] - truth);
      }
  EXPECT_LT(guidedError, 0.2 * nearestError);
}

TEST(ComponentUpsampler, NamesWhatIsMissingOrDoesNotFit) {
  const auto expectError = [](const FrameImage& low, const FrameImage& high, const std::string& part,
                               const UpsampleSettings& settings = settingsOf(1e-3f)) {
    try {
      upsampleFrame(low, high, settings);
      ADD_FAILURE() << "no error; expected one naming " << part;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  const FrameImage low = makeLow([](int, int, int, int) { return 1.0f; });
  const FrameImage high = makeHighFeatures();
  EXPECT_NO_THROW(upsampleFrame(low, high, settingsOf(1e-3f)));

  FrameImage noIrradiance(kLowWidth, kLowHeight);
  noIrradiance.attributes() = low.attributes();
  for (const std::string& name : low.channelNames())
    if (name != "residual.irradiance.G") noIrradiance.addChannel(name) = low.channel(name);
  expectError(noIrradiance, high, "\"residual.irradiance.G\"");

  FrameImage noNormal(kFullWidth, kFullHeight);
  noNormal.attributes() = high.attributes();
  for (const std::string& name : high.channelNames())
    if (name != "diffuse.normal.Y") noNormal.addChannel(name) = high.channel(name);
  expectError(low, noNormal, "\"diffuse.normal.Y\"");

  FrameImage undecomposed = low;
  undecomposed.attributes().erase("pathfarm.decomposition");
  expectError(undecomposed, high, "pathfarm.decomposition");

  FrameImage otherDecomposition = high;
  otherDecomposition.attributes()["pathfarm.decomposition"] = "glass=ETTD.*,residual";
  expectError(low, otherDecomposition, "glass=ETTD.*,residual");

  FrameImage wrongSize(kFullWidth + 2, kFullHeight);
  wrongSize.paste(high, 0, 0);
  expectError(low, wrongSize, "needs 16x12 features, not 18x12");
  UpsampleSettings factor3 = settingsOf(1e-3f);
  factor3.guided.factor = 3;
  EXPECT_THROW(upsampleFrame(low, high, factor3), std::invalid_argument);

  UpsampleSettings depthGuide = settingsOf(1e-3f);
  depthGuide.guideBuffers = {"normal", "depth"};
  expectError(low, high, "\"diffuse.depth.Z\"", depthGuide);
  UpsampleSettings customGuide = settingsOf(1e-3f);
  customGuide.guideBuffers = {"normal", "curvature"};
  expectError(low, high, "\"diffuse.curvature.*\"", customGuide);
}

TEST(ComponentUpsampler, UpsamplesEveryComponentTheAttributeNames) {
  // Three components; "residual" is implied when the attribute does not list it.
  for (const std::string decomposition : {"a=ED,b=ED.+,residual", "a=ED,b=ED.+"}) {
    FrameImage low(2, 2), high(4, 4);
    low.attributes()["pathfarm.decomposition"] = decomposition;
    int k = 0;
    for (const std::string name : {"a", "b", "residual"}) {
      ++k;
      for (int c = 0; c < 3; ++c) {
        low.addChannel(name + ".irradiance." + kUpsampledChannels[c]).assign(4, static_cast<float>(k));
        high.addChannel(name + ".reflectance." + kUpsampledChannels[c]).assign(16, 0.5f);
        high.addChannel(name + ".normal." + kXyz[c]).assign(16, c == 2 ? 1.0f : 0.0f);
        high.addChannel(name + ".emission." + kUpsampledChannels[c]);
      }
    }
    UpsampleSettings settings = settingsOf(1e-3f);
    settings.guided.radius = 1;
    const FrameImage out = upsampleFrame(low, high, settings);
    EXPECT_EQ(out.channelNames(),
              (std::vector<std::string>{"R", "G", "B", "a.color.R", "a.irradiance.R", "a.color.G", "a.irradiance.G",
                                        "a.color.B", "a.irradiance.B", "b.color.R", "b.irradiance.R", "b.color.G",
                                        "b.irradiance.G", "b.color.B", "b.irradiance.B", "residual.color.R",
                                        "residual.irradiance.R", "residual.color.G", "residual.irradiance.G",
                                        "residual.color.B", "residual.irradiance.B", "rerender.Y"}));
    for (const float v : out.channel("b.color.G")) EXPECT_NEAR(v, 1.0f, 1e-6f);
    for (const float v : out.channel("G")) EXPECT_NEAR(v, 3.0f, 1e-6f);  // (1 + 2 + 3) * 0.5
  }
}

TEST(BoxDownsample, AveragesEveryChannelAsALowResolutionRenderWouldHaveIt) {
  FrameImage high(4, 2);
  high.attributes()["pathfarm.decomposition"] = "d=ED,residual";
  const auto fill = [&](const std::string& name, std::vector<float> values) { high.addChannel(name) = std::move(values); };
  fill("R", {1, 2, 5, 6, 3, 4, 7, 8});
  fill("variance.R", {4, 4, 8, 8, 4, 4, 8, 8});
  fill("d.color.R", {0.5f, 0.5f, 1, 1, 0.5f, 0.5f, 1, 0});
  fill("d.reflectance.R", {0.5f, 0.5f, 0.5f, 0.5f, 1, 1, 0.5f, 0});
  fill("d.irradiance.R", {1, 1, 2, 2, 0.5f, 0.5f, 2, 0});
  fill("d.normal.X", {1, 0, 0, 0, 1, 0, 0, 0});
  fill("d.normal.Y", {0, 1, 0, 0, 0, 1, 0, 0});
  fill("d.normal.Z", {0, 0, 1, 1, 0, 0, 1, 1});
  fill("d.objectid.Y", {3, 4, 5, 6, 7, 8, 9, 10});
  fill("motion.X", {2, 2, -4, -4, 2, 2, -4, -4});
  fill("silhouette.Y", {0, 0, 0, 1, 0, 0, 0, 0});
  fill("d.depth.Z", {1, 2, 3, 4, 5, 6, 7, 8});

  const FrameImage low = boxDownsample(high, 2);
  ASSERT_EQ(low.width(), 2);
  ASSERT_EQ(low.height(), 1);
  EXPECT_EQ(low.channelNames(), high.channelNames());
  EXPECT_EQ(low.attributes(), high.attributes());
  EXPECT_EQ(low.channel("R"), (std::vector<float>{2.5f, 6.5f}));
  EXPECT_EQ(low.channel("d.depth.Z"), (std::vector<float>{3.5f, 5.5f}));
  EXPECT_EQ(low.channel("variance.R"), (std::vector<float>{1.0f, 2.0f}));  // mean / 4
  // mean color / mean reflectance: 0.5 / 0.75 and 0.75 / 0.375.
  EXPECT_FLOAT_EQ(low.channel("d.irradiance.R")[0], 0.5f / 0.75f);
  EXPECT_FLOAT_EQ(low.channel("d.irradiance.R")[1], 2.0f);
  EXPECT_FLOAT_EQ(low.channel("d.normal.X")[0], 1.0f / std::sqrt(2.0f));
  EXPECT_FLOAT_EQ(low.channel("d.normal.Y")[0], 1.0f / std::sqrt(2.0f));
  EXPECT_EQ(low.channel("d.normal.Z")[0], 0.0f);
  EXPECT_FLOAT_EQ(low.channel("d.normal.Z")[1], 1.0f);
  EXPECT_EQ(low.channel("d.objectid.Y"), (std::vector<float>{3, 5}));
  EXPECT_EQ(low.channel("motion.X"), (std::vector<float>{1, -2}));  // low-resolution pixels
  EXPECT_EQ(low.channel("silhouette.Y"), (std::vector<float>{0, 1}));

  EXPECT_THROW(boxDownsample(high, 3), std::invalid_argument);
  EXPECT_THROW(boxDownsample(high, 0), std::invalid_argument);
  EXPECT_EQ(boxDownsample(high, 1).channel("d.irradiance.R"), high.channel("d.irradiance.R"));
}

}  // namespace
}  // namespace pathfarm
