// Decomposed renders: components add up to the beauty, effective irradiance inverts, paths
// land in the component their expression names, and primary motion is exact.
#include <gtest/gtest.h>

#include "renderer/setup/auto_decomposition.h"
#include "renderer/decomposition/effective_irradiance.h"
#include "renderer/integrators/frame_renderer.h"
#include "test_support.h"
#include "tests/renderer/sky_map.h"

namespace pathfarm {
namespace {

const char* kComponents[] = {"diffuse_direct", "diffuse_indirect", "reflection", "transmission", "residual"};

FrameImage renderDecomposed(const Scene& scene, int width, int height, int spp, int64_t frame = 0,
                            bool decompose = true) {
  RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.spp = spp;
  settings.maxDepth = 8;
  if (decompose) settings.decomposition = std::make_shared<Decomposition>(Decomposition::standard());
  return FrameRenderer(scene, settings).render(frame);
}

double channelSum(const FrameImage& image, const std::string& name) {
  double sum = 0;
  for (float v : image.channel(name)) sum += v;
  return sum;
}

void expectComponentsAddUpToBeauty(const Scene& scene, const std::string& label) {
  const FrameImage decomposed = renderDecomposed(scene, 24, 18, 4, 3);
  const FrameImage plain = renderDecomposed(scene, 24, 18, 4, 3, false);
  for (const char* channel : {"R", "G", "B"}) {
    // The beauty does not change by a bit when the decomposition is on.
    EXPECT_EQ(decomposed.channel(channel), plain.channel(channel)) << label;
    const auto& beauty = decomposed.channel(channel);
    for (size_t p = 0; p < beauty.size(); ++p) {
      double sum = 0;
      for (const char* c : kComponents) sum += decomposed.channel(std::string(c) + ".color." + channel)[p];
      ASSERT_NEAR(sum, beauty[p], 1e-5 * std::abs(beauty[p]) + 1e-6) << label << " pixel " << p;
      // Directly seen light is a part of its component's color.
      for (const char* c : kComponents) {
        const float direct = decomposed.channel(std::string(c) + ".emission." + channel)[p];
        const float color = decomposed.channel(std::string(c) + ".color." + channel)[p];
        ASSERT_GE(direct, 0.0f) << label << " " << c << " pixel " << p;
        ASSERT_LE(direct, color * (1 + 1e-5f) + 1e-6f) << label << " " << c << " pixel " << p;
      }
    }
  }
}

TEST(DecomposedRender, ComponentsAddUpToTheBeautyOfTheSameSamples) {
  for (const char* path : {"scenes/cornell/scene.json", "scenes/materials/scene.json", "scenes/dolly/scene.json",
                           "scenes/creature/scene.json"}) {
    expectComponentsAddUpToBeauty(loadScene(test_support::sourceDir() / path), path);
  }
  const Scene lobes = test_support::sceneFromJson(R"({
    "camera": {"position": [0, 1, 4], "look_at": [0, 0.5, 0], "fov": 50},
    "materials": {"floor": {"type": "diffuse", "reflectance": 0.6},
                  "plastic": {"type": "plastic", "reflectance": [0.6, 0.2, 0.1]},
                  "rough_plastic": {"type": "rough_plastic", "reflectance": [0.1, 0.5, 0.2], "alpha": 0.05},
                  "metal": {"type": "rough_conductor", "alpha": 0.05},
                  "frosted": {"type": "rough_dielectric", "alpha": 0.05}},
    "environment": {"radiance": [0.3, 0.3, 0.35]},
    "shapes": [
      {"type": "rectangle", "size": [8, 8], "material": "floor", "transform": {"rotate": {"axis": [1, 0, 0], "angle": -90}}},
      {"type": "sphere", "radius": 0.4, "material": "plastic", "transform": {"translate": [-1.2, 0.4, 0]}},
      {"type": "sphere", "radius": 0.4, "material": "rough_plastic", "transform": {"translate": [-0.4, 0.4, 0]}},
      {"type": "sphere", "radius": 0.4, "material": "metal", "transform": {"translate": [0.4, 0.4, 0]}},
      {"type": "sphere", "radius": 0.4, "material": "frosted", "transform": {"translate": [1.2, 0.4, 0]}},
      {"type": "rectangle", "size": [1, 1], "material": "floor", "emission": 8,
       "transform": {"translate": [0, 2.5, 1], "rotate": {"axis": [1, 0, 0], "angle": 90}}}]
  })");
  expectComponentsAddUpToBeauty(lobes, "plastic, rough plastic, rough conductor, rough dielectric");
}

// The metallic-roughness material has three lobes at once (R, D, T): each routes its part.
TEST(DecomposedRender, MetallicRoughnessComponentsAddUpToTheBeauty) {
  const Scene scene = test_support::sceneFromJson(R"({
    "camera": {"position": [0, 1, 4], "look_at": [0, 0.5, 0], "fov": 50},
    "materials": {"floor": {"type": "diffuse", "reflectance": 0.6},
                  "sharp": {"type": "metallic_roughness", "base_color": [0.8, 0.5, 0.3], "metallic": 0.3,
                            "roughness": 0.2, "transmission": 0.5},
                  "smooth": {"type": "metallic_roughness", "base_color": [0.3, 0.6, 0.8], "metallic": 0,
                             "roughness": 0, "transmission": 0.4},
                  "rough": {"type": "metallic_roughness", "base_color": 0.7, "metallic": 0.5, "roughness": 0.8}},
    "environment": {"radiance": [0.3, 0.3, 0.35]},
    "shapes": [
      {"type": "rectangle", "size": [8, 8], "material": "floor", "transform": {"rotate": {"axis": [1, 0, 0], "angle": -90}}},
      {"type": "sphere", "radius": 0.4, "material": "sharp", "transform": {"translate": [-0.9, 0.4, 0]}},
      {"type": "sphere", "radius": 0.4, "material": "smooth", "transform": {"translate": [0, 0.4, 0]}},
      {"type": "sphere", "radius": 0.4, "material": "rough", "transform": {"translate": [0.9, 0.4, 0]}},
      {"type": "rectangle", "size": [1, 1], "material": "floor", "emission": 8,
       "transform": {"translate": [0, 2.5, 1], "rotate": {"axis": [1, 0, 0], "angle": 90}}}]
  })");
  expectComponentsAddUpToBeauty(scene, "metallic roughness");
}

// The same under an environment map with a sun and a bright lower half, turned: light by
// direction reaches every component, and directly seen sky is the residual's.
TEST(DecomposedRender, ComponentsAddUpUnderAnEnvironmentMap) {
  const std::filesystem::path map = test_support::skyMapFolder() / "decomposed_sun.hdr";
  test_support::writeSkyMap(map, 64, 32, test_support::skyMapTexels(64, 32, [](Vec3f d) {
                              return d.y < 0 ? Rgb(0.5f, 0.25f, 0.125f) : d.x > 0.9f ? Rgb(100) : Rgb(0.25f, 0.5f, 1);
                            }));
  const Scene scene = test_support::sceneFromJson(R"({
    "camera": {"position": [0, 1, 4], "look_at": [0, 0.5, 0], "fov": 50},
    "materials": {"floor": {"type": "diffuse", "reflectance": 0.6},
                  "metal": {"type": "rough_conductor", "alpha": 0.05},
                  "mirror": {"type": "conductor", "specular_color": 0.9},
                  "glass": {"type": "dielectric", "ior": 1.5}},
    "environment": {"map": ")" + map.string() + R"(", "strength": 0.8, "rotation": 45},
    "shapes": [
      {"type": "rectangle", "size": [8, 8], "material": "floor", "transform": {"rotate": {"axis": [1, 0, 0], "angle": -90}}},
      {"type": "sphere", "radius": 0.4, "material": "metal", "transform": {"translate": [-0.9, 0.4, 0]}},
      {"type": "sphere", "radius": 0.4, "material": "mirror", "transform": {"translate": [0, 0.4, 0]}},
      {"type": "sphere", "radius": 0.4, "material": "glass", "transform": {"translate": [0.9, 0.4, 0]}}]
  })");
  expectComponentsAddUpToBeauty(scene, "environment map");
}

TEST(DecomposedRender, IrradianceTimesReflectanceGivesTheColorBack) {
  const FrameImage image = renderDecomposed(loadScene(test_support::sourceDir() / "scenes/materials/scene.json"), 32, 18, 4);
  int guarded = 0;
  for (const char* c : kComponents) {
    for (const char* ch : {".R", ".G", ".B"}) {
      const auto& color = image.channel(std::string(c) + ".color" + ch);
      const auto& irradiance = image.channel(std::string(c) + ".irradiance" + ch);
      const auto& reflectance = image.channel(std::string(c) + ".reflectance" + ch);
      for (size_t p = 0; p < color.size(); ++p) {
        guarded += reflectance[p] < kReflectanceGuard;
        ASSERT_NEAR(modulateIrradiance(irradiance[p], reflectance[p]), color[p], 1e-6f * std::abs(color[p]) + 1e-12f);
      }
    }
  }
  EXPECT_GT(guarded, 0) << "no pixel exercised the guard";
}

// Samples traced for the reflectance alone (RenderSettings::reflectanceSpp) follow the
// same camera rays and lobe choices as full paths of the same sample indices, so a 4-spp
// render with 16 reflectance samples has the reflectance of a 16-spp render, computed by
// the full path tracer, and everything else of the 4-spp render.
TEST(DecomposedRender, ReflectanceSamplesGiveTheReflectanceOfFullPathsWithTheirIndices) {
  for (const char* path : {"scenes/dolly/scene.json", "scenes/materials/scene.json"}) {
    const Scene scene = loadScene(test_support::sourceDir() / path);
    RenderSettings settings;
    settings.width = 40;
    settings.height = 24;
    settings.maxDepth = 8;
    settings.decomposition = std::make_shared<Decomposition>(Decomposition::standard());
    settings.spp = 16;
    const FrameImage full = FrameRenderer(scene, settings).render(2);
    settings.spp = 4;
    const FrameImage few = FrameRenderer(scene, settings).render(2);
    settings.reflectanceSpp = 16;
    const FrameImage sharpened = FrameRenderer(scene, settings).render(2);
    EXPECT_EQ(sharpened.attributes().at("pathfarm.reflectance_spp"), "16");
    EXPECT_EQ(sharpened.attributes().at("pathfarm.spp"), "4");
    double changed = 0;
    for (const std::string& name : few.channelNames()) {
      const bool reflectance = name.find(".reflectance.") != std::string::npos;
      const bool irradiance = name.find(".irradiance.") != std::string::npos;  // color / reflectance
      if (!reflectance) {
        if (!irradiance) EXPECT_TRUE(sharpened.channel(name) == few.channel(name)) << path << " " << name;
        continue;
      }
      // The residual's paths (E T R T D, ...) may meet their first D vertex after Russian
      // roulette has ended the full path, which a reflectance sample never does.
      if (name.rfind("residual.", 0) == 0) continue;
      const std::vector<float>&expected = full.channel(name), &actual = sharpened.channel(name);
      for (size_t p = 0; p < expected.size(); ++p) {
        ASSERT_NEAR(actual[p], expected[p], 1e-5f * expected[p] + 1e-6f) << path << " " << name << " pixel " << p;
        changed += std::abs(actual[p] - few.channel(name)[p]);
      }
    }
    EXPECT_GT(changed, 0.0) << path << ": the reflectance samples changed nothing";
  }
}

bool isMotionChannel(const std::string& name) {
  for (const char* buffer : {"motion.", "motion_back.", "motion_valid.", "silhouette."})
    if (name.rfind(buffer, 0) == 0 || name.find(std::string(".") + buffer) != std::string::npos) return true;
  return false;
}

// A render that does not measure motion (RenderSettings::motion) has every other channel's
// bits, and zero motion.
TEST(DecomposedRender, WithoutMotionEveryOtherChannelKeepsItsBits) {
  const Scene scene = loadScene(test_support::sourceDir() / "scenes/dolly/scene.json");
  RenderSettings settings;
  settings.width = 40;
  settings.height = 24;
  settings.spp = 4;
  settings.decomposition = std::make_shared<Decomposition>(Decomposition::standard());
  const FrameImage moving = FrameRenderer(scene, settings).render(5);
  settings.motion = false;
  const FrameImage still = FrameRenderer(scene, settings).render(5);
  EXPECT_EQ(still.attributes().at("pathfarm.motion"), "not measured");
  ASSERT_EQ(still.channelNames(), moving.channelNames());
  size_t motionChannels = 0;
  for (const std::string& name : moving.channelNames()) {
    if (!isMotionChannel(name)) {
      EXPECT_TRUE(still.channel(name) == moving.channel(name)) << name;
      continue;
    }
    ++motionChannels;
    for (const float v : still.channel(name)) ASSERT_EQ(v, 0.0f) << name;
  }
  EXPECT_EQ(motionChannels, 5u * 5u + 5u);  // 5 per component; the frame's 2 + 2 and its silhouettes
  // The dolly's camera moves, so the motion that was skipped is not zero.
  EXPECT_GT(channelSum(moving, "motion.X") * channelSum(moving, "motion.X"), 0.0);
  EXPECT_GT(channelSum(moving, "reflection.motion_valid.Y"), 0.0) << "no specular motion to skip";
}

// A camera close in front of a sphere that fills the view, lit by an area light and a
// dim environment.
Scene sphereFillingTheView(const char* material) {
  return test_support::sceneFromJson(std::string(R"({
    "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "fov": 8},
    "materials": {"m": )") + material + R"(, "white": {"type": "diffuse", "reflectance": 0.8}},
    "environment": {"radiance": 0.2},
    "shapes": [{"type": "sphere", "radius": 1, "material": "m"},
               {"type": "rectangle", "size": [10, 10], "material": "white",
                "transform": {"translate": [0, 0, -3]}},
               {"type": "rectangle", "size": [2, 2], "material": "white", "emission": 5,
                "transform": {"translate": [0, 0, 4], "rotate": {"axis": [0, 1, 0], "angle": 180}}}]
  })");
}

TEST(DecomposedRender, MirrorEnergyGoesToReflectionNotToTheDiffuseComponents) {
  const FrameImage image = renderDecomposed(sphereFillingTheView(R"({"type": "conductor", "specular_color": 0.9})"), 8, 8, 16);
  for (const char* ch : {".R", ".G", ".B"}) {
    EXPECT_EQ(channelSum(image, std::string("diffuse_direct.color") + ch), 0.0);
    EXPECT_EQ(channelSum(image, std::string("diffuse_indirect.color") + ch), 0.0);
    EXPECT_GT(channelSum(image, std::string("reflection.color") + ch), 0.0);
    EXPECT_EQ(channelSum(image, std::string("transmission.color") + ch), 0.0);  // no glass
  }
  // Features through the mirror: the centre pixel's reflection shows the light behind
  // the camera (object 3), and its normal faces back along the view (+z towards the sphere is -z).
  const size_t centre = 4 * 8 + 4;
  EXPECT_EQ(image.channel("reflection.objectid.Y")[centre], 3.0f);
  EXPECT_NEAR(image.channel("reflection.normal.Z")[centre], -1.0f, 1e-2f);
  // The light itself is seen through the mirror without a diffuse vertex (E R L): it is
  // the residual's directly seen light, 0.9 x 5, and none of the reflection component's.
  EXPECT_NEAR(image.channel("residual.emission.G")[centre], 4.5f, 0.05f);
  EXPECT_FLOAT_EQ(image.channel("residual.emission.G")[centre], image.channel("residual.color.G")[centre]);
  EXPECT_EQ(channelSum(image, "reflection.emission.G"), 0.0);
  // Nothing moves: the mirror's path is tracked with exactly zero motion, without a walk.
  EXPECT_EQ(image.channel("reflection.motion_valid.Y")[centre], 1.0f);
  EXPECT_EQ(image.channel("reflection.motion.X")[centre], 0.0f);
  EXPECT_EQ(image.channel("reflection.motion_back.Y")[centre], 0.0f);
}

// A mirror sphere, a glass sphere and a diffuse floor under a constant sky of 0.5.
TEST(DecomposedRender, DirectlySeenLightIsTheLightOfPathsWithoutADiffuseVertex) {
  const Scene scene = test_support::sceneFromJson(R"({
    "camera": {"position": [0, 0.6, 4], "look_at": [0, 0.4, 0], "fov": 40},
    "materials": {"floor": {"type": "diffuse", "reflectance": 0.5},
                  "mirror": {"type": "conductor", "specular_color": 0.9},
                  "glass": {"type": "dielectric", "ior": 1.5}},
    "environment": {"radiance": 0.5},
    "shapes": [
      {"type": "rectangle", "size": [4, 4], "material": "floor", "transform": {"rotate": {"axis": [1, 0, 0], "angle": -90}}},
      {"type": "sphere", "radius": 0.4, "material": "mirror", "transform": {"translate": [-0.5, 0.4, 0]}},
      {"type": "sphere", "radius": 0.4, "material": "glass", "transform": {"translate": [0.5, 0.4, 0]}}]
  })");
  const int width = 32, height = 24;
  const FrameImage image = renderDecomposed(scene, width, height, 8);
  // Every expression of the standard decomposition needs a D vertex: only the residual
  // can receive light from paths without one.
  for (const char* c : {"diffuse_direct", "diffuse_indirect", "reflection", "transmission"})
    EXPECT_EQ(channelSum(image, std::string(c) + ".emission.G"), 0.0) << c;
  // The top row sees the sky: all of its light is the residual's, and directly seen.
  for (int x = 0; x < width; ++x) {
    EXPECT_FLOAT_EQ(image.channel("G")[static_cast<size_t>(x)], 0.5f) << x;
    EXPECT_FLOAT_EQ(image.channel("residual.emission.G")[static_cast<size_t>(x)], 0.5f) << x;
  }
  // The spheres show the sky too (reflected, and refracted through the glass): directly
  // seen light appears on them, and it never exceeds the residual's color.
  const auto sphereDirect = [&](int x) {
    return image.channel("residual.emission.G")[static_cast<size_t>(height / 2 * width + x)];
  };
  EXPECT_GT(sphereDirect(width / 2 - width / 8), 0.0f);
  EXPECT_GT(sphereDirect(width / 2 + width / 8), 0.0f);
}

TEST(DecomposedRender, SeeThroughGlassEnergyGoesToTransmission) {
  const FrameImage image = renderDecomposed(sphereFillingTheView(R"({"type": "dielectric", "ior": 1.5})"), 8, 8, 16);
  const double transmission = channelSum(image, "transmission.color.G");
  EXPECT_GT(transmission, 0.0);
  EXPECT_EQ(channelSum(image, "diffuse_direct.color.G"), 0.0);
  EXPECT_EQ(channelSum(image, "diffuse_indirect.color.G"), 0.0);
  // What the glass shows (the wall behind) dominates what it reflects.
  EXPECT_GT(transmission, channelSum(image, "residual.color.G") + channelSum(image, "reflection.color.G"));
}

// A square card facing the camera at distance 5 slides by (0.1, 0.05) per frame; the
// camera looks down -z with a 30 degree field of view at 64x64 pixels.
TEST(DecomposedRender, TranslationGivesExactlyItsScreenMotion) {
  const Scene scene = test_support::sceneFromJson(R"({
    "fps": 10,
    "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov": 30},
    "materials": {"m": {"type": "diffuse", "reflectance": 0.5}},
    "environment": {"radiance": 1},
    "shapes": [{"type": "rectangle", "size": [1.5, 1.5], "material": "m", "object_id": 9,
                "animation": {"translate": [{"frame": 0, "value": [-0.5, 0, 0]},
                                            {"frame": 10, "value": [0.5, 0.5, 0]}]}}]
  })");
  const FrameImage image = renderDecomposed(scene, 64, 64, 2, 4);
  const double pixelsPerUnit = 32.0 / (5.0 * std::tan(15.0 * kPi / 180.0));
  const float expectedX = static_cast<float>(0.1 * pixelsPerUnit), expectedY = static_cast<float>(-0.05 * pixelsPerUnit);
  int inside = 0;
  for (size_t p = 0; p < image.pixelCount(); ++p) {
    if (image.channel("diffuse_direct.objectid.Y")[p] != 9.0f || image.channel("silhouette.Y")[p] != 0.0f) continue;
    ++inside;
    ASSERT_NEAR(image.channel("motion.X")[p], expectedX, 1e-3f) << p;
    ASSERT_NEAR(image.channel("motion.Y")[p], expectedY, 1e-3f) << p;
    ASSERT_NEAR(image.channel("motion_back.X")[p], -expectedX, 1e-3f) << p;
    ASSERT_NEAR(image.channel("diffuse_direct.motion.X")[p], expectedX, 1e-3f) << p;
    ASSERT_EQ(image.channel("diffuse_direct.motion_valid.Y")[p], 1.0f);
  }
  EXPECT_GT(inside, 200);
  // The background does not move: the camera stands still.
  EXPECT_EQ(image.channel("motion.X")[0], 0.0f);
}

TEST(DecomposedRender, RotationAndCameraPanGiveTheirMotion) {
  // The card turns about the view axis by 3 degrees a frame while the camera pans
  // sideways by 0.05 a frame: every pixel's motion is known in closed form.
  const Scene scene = test_support::sceneFromJson(R"({
    "fps": 10,
    "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov": 30,
               "animation": {"translate": [{"frame": 0, "value": [0, 0, 5]}, {"frame": 10, "value": [0.5, 0, 5]}]}},
    "materials": {"m": {"type": "diffuse", "reflectance": 0.5}},
    "shapes": [{"type": "rectangle", "size": [6, 6], "material": "m", "object_id": 3,
                "animation": {"rotate": [{"frame": 0, "axis": [0, 0, 1], "angle": 0},
                                         {"frame": 10, "axis": [0, 0, 1], "angle": 30}]}}]
  })");
  const FrameImage image = renderDecomposed(scene, 32, 32, 1, 5);
  const double pixelsPerUnit = 16.0 / (5.0 * std::tan(15.0 * kPi / 180.0));
  // With one sample a pixel, the card's uv says exactly which point the sample saw: the
  // card's local point (6u - 3, 6v - 3), turned by 15 degrees at frame 5 (t = 0.5 s).
  const auto screen = [&](double angleDegrees, double cameraX, double u, double v) {
    const double a = angleDegrees * kPi / 180.0, lx = 6 * u - 3, ly = 6 * v - 3;
    const double wx = lx * std::cos(a) - ly * std::sin(a), wy = lx * std::sin(a) + ly * std::cos(a);
    return std::pair{16.0 + (wx - cameraX) * pixelsPerUnit, 16.0 - wy * pixelsPerUnit};
  };
  int checked = 0;
  for (size_t p = 0; p < image.pixelCount(); ++p) {
    if (image.channel("diffuse_direct.objectid.Y")[p] != 3.0f) continue;
    const double u = image.channel("diffuse_direct.uv.X")[p], v = image.channel("diffuse_direct.uv.Y")[p];
    const auto now = screen(15, 0.25, u, v), next = screen(18, 0.30, u, v), previous = screen(12, 0.20, u, v);
    ASSERT_NEAR(image.channel("motion.X")[p], next.first - now.first, 1e-3) << p;
    ASSERT_NEAR(image.channel("motion.Y")[p], next.second - now.second, 1e-3) << p;
    ASSERT_NEAR(image.channel("motion_back.X")[p], previous.first - now.first, 1e-3) << p;
    ASSERT_NEAR(image.channel("motion_back.Y")[p], previous.second - now.second, 1e-3) << p;
    ++checked;
  }
  EXPECT_EQ(checked, 32 * 32);
}

TEST(DecomposedRender, NoGlassMeansAnEmptyTransmission) {
  const FrameImage image = renderDecomposed(loadScene(test_support::sourceDir() / "scenes/materials/scene.json"), 16, 9, 2);
  EXPECT_EQ(channelSum(image, "transmission.color.G"), 0.0) << "frosted glass sphere is rough: T counts as D there";
  EXPECT_EQ(image.attributes().at("pathfarm.decomposition"),
            "diffuse_direct=ED,diffuse_indirect=ED.+,reflection=ERD.*,transmission=ETTD.*,residual");
  EXPECT_EQ(image.attributes().at("pathfarm.specular_components"), "reflection,transmission");
}

// Specular: the camera's first vertex cannot be the component's non-specular one. E.D
// and E.*D may end at the first hit, so they are not; the residual never is.
TEST(DecomposedRender, SpecularComponentsAreThoseThatCannotEndAtTheFirstHit) {
  const Decomposition d = Decomposition::parse("direct=ED,any=E.D,glossy=E(R|T)D,deep=ETTTTD.*,late=E.*D");
  const std::vector<bool> expected = {false, false, true, true, false, false};
  for (int k = 0; k < d.size(); ++k) EXPECT_EQ(d.isSpecular(k), expected[static_cast<size_t>(k)]) << d.name(k);
  EXPECT_EQ(d.describeSpecular(), "glossy,deep");
}

}  // namespace
}  // namespace pathfarm

namespace pathfarm {
namespace {

std::vector<std::string> componentNames(const Decomposition& d) {
  std::vector<std::string> names;
  for (int k = 0; k < d.size(); ++k) names.push_back(d.name(k));
  return names;
}

TEST(AutoDecomposition, ModelsOnlyWhatTheSceneCanProduce) {
  using Names = std::vector<std::string>;
  // Mirror and glass: both specular components (the glass sphere is seen through once).
  const Scene cornell = loadScene(test_support::sourceDir() / "scenes/cornell/scene.json");
  const Names cornellNames = componentNames(chooseDecomposition(cornell));
  EXPECT_EQ(Names(cornellNames.begin(), cornellNames.begin() + 4),
            (Names{"diffuse_direct", "diffuse_indirect", "reflection", "transmission"}));
  // Smooth coatings and a glossy metal but only rough (D) glass: no transmission.
  const Scene materials = loadScene(test_support::sourceDir() / "scenes/materials/scene.json");
  EXPECT_EQ(componentNames(chooseDecomposition(materials)),
            (Names{"diffuse_direct", "diffuse_indirect", "reflection", "residual"}));
  // Only diffuse surfaces: nothing specular at all.
  const Scene diffuse = test_support::sceneFromJson(R"({
    "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0]},
    "materials": {"m": {"type": "diffuse"}}, "environment": {"radiance": 1},
    "shapes": [{"type": "sphere", "radius": 1, "material": "m"}]})");
  EXPECT_EQ(componentNames(chooseDecomposition(diffuse)), (Names{"diffuse_direct", "diffuse_indirect", "residual"}));
}

TEST(AutoDecomposition, AddsTheDeepTransmissionWhenAProbeShowsItMatters) {
  // A lit wall seen through two glass spheres one behind the other: light crosses four
  // glass surfaces on its way to the camera.
  const Scene scene = test_support::sceneFromJson(R"({
    "camera": {"position": [0, 0, 6], "look_at": [0, 0, 0], "fov": 12},
    "materials": {"glass": {"type": "dielectric", "ior": 1.3}, "wall": {"type": "diffuse", "reflectance": 0.8}},
    "environment": {"radiance": 0.05},
    "shapes": [{"type": "sphere", "radius": 0.8, "material": "glass", "transform": {"translate": [0, 0, 1]}},
               {"type": "sphere", "radius": 0.8, "material": "glass", "transform": {"translate": [0, 0, -1]}},
               {"type": "rectangle", "size": [20, 20], "material": "wall", "emission": 1,
                "transform": {"translate": [0, 0, -4]}}]})");
  const Decomposition chosen = chooseDecomposition(scene);
  EXPECT_EQ(chosen.name(chosen.size() - 2), "transmission_deep");
  EXPECT_EQ(chosen.components().back().expression, "ETTTTD.*");
}

}  // namespace
}  // namespace pathfarm
