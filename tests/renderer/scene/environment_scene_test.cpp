// The environment key of a scene file: a constant, a map with strength and rotation
// (.hdr and .exr), and errors that name the file and the key.
#include <gtest/gtest.h>

#include <fstream>

#include "image/exr_io.h"
#include "renderer/scene/scene_loader.h"
#include "test_support.h"
#include "tests/renderer/sky_map.h"

namespace pathfarm {
namespace {

namespace fs = std::filesystem;

fs::path folder() { return test_support::skyMapFolder() / "scene"; }

Scene withEnvironment(const std::string& environment) {
  return test_support::sceneFromJson(R"({
    "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]},
    "materials": {"m": {"type": "diffuse"}},
    "environment": )" + environment + R"(,
    "shapes": [{"type": "sphere", "radius": 1, "material": "m"}]})",
                                     folder());
}

std::string environmentErrorOf(const std::string& environment) {
  return test_support::sceneErrorOf([&] { withEnvironment(environment); });
}

// Upper hemisphere 1, lower 4: a mirrored map would read 4 looking up.
void writeHemisphereSky() {
  test_support::writeSkyMap(folder() / "hemisphere.hdr", 16, 8,
                            test_support::hemisphereSkyTexels(16, 8, Rgb(1), Rgb(4)));
}

TEST(EnvironmentScene, RadianceIsAConstant) {
  const Scene scene = withEnvironment(R"({"radiance": [1, 2, 3]})");
  EXPECT_EQ(scene.environment.radiance({0, 1, 0}).g, 2);
  EXPECT_EQ(scene.environment.radiance({0.6f, -0.8f, 0}).b, 3);
}

TEST(EnvironmentScene, MapFromHdrWithStrength) {
  writeHemisphereSky();
  const Scene scene = withEnvironment(R"({"map": "hemisphere.hdr", "strength": 0.5})");
  EXPECT_FLOAT_EQ(scene.environment.radiance({0, 1, 0}).r, 0.5f);
  EXPECT_FLOAT_EQ(scene.environment.radiance({0, -1, 0}).g, 2.0f);
  EXPECT_FLOAT_EQ(scene.environment.meanLuminance(), 0.5f * 2.5f);
}

TEST(EnvironmentScene, MapFromExrWithRotation) {
  // Red where the map's centre is (+x), green a quarter turn on (+z), else black.
  const int w = 8, h = 4;
  FrameImage image(w, h);
  for (const char* c : {"R", "G", "B"}) image.addChannel(c);
  for (int y = 1; y < 3; ++y) {
    image.channel("R")[static_cast<size_t>(y * w + 4)] = 2;  // u in [1/2, 5/8): just past +x towards +z
    image.channel("G")[static_cast<size_t>(y * w + 6)] = 2;  // u in [3/4, 7/8): just past +z
  }
  writeExr(folder() / "marks.exr", image);
  const Scene scene = withEnvironment(R"({"map": "marks.exr", "rotation": 90})");
  // Turned 90 degrees about +y: the map's +x faces -z, its +z faces +x. Look at the
  // texel centres, u = 9/16 and 13/16, on the horizon.
  const float a = 2 * static_cast<float>(M_PI) / 16;
  EXPECT_NEAR(scene.environment.radiance({std::sin(a), 0, -std::cos(a)}).r, 2, 1e-5f);
  EXPECT_NEAR(scene.environment.radiance({std::cos(a), 0, std::sin(a)}).g, 2, 1e-5f);
  EXPECT_NEAR(scene.environment.radiance({std::cos(a), 0, std::sin(a)}).r, 0, 1e-5f);
}

TEST(EnvironmentScene, ErrorsNameTheFileAndKey) {
  writeHemisphereSky();
  EXPECT_NE(environmentErrorOf(R"({"radiance": 1, "map": "hemisphere.hdr"})").find("environment: give either radiance or map"),
            std::string::npos);
  EXPECT_NE(environmentErrorOf(R"({"strength": 2})").find("environment: expected radiance or map"), std::string::npos);
  EXPECT_NE(environmentErrorOf(R"({"radiance": 1, "rotation": 10})").find("apply to a map only"), std::string::npos);
  EXPECT_NE(environmentErrorOf(R"({"map": "hemisphere.hdr", "strength": -1})").find("environment.strength"), std::string::npos);
  EXPECT_NE(environmentErrorOf(R"({"map": "hemisphere.hdr", "gain": 2})").find("gain"), std::string::npos);

  const std::string missing = environmentErrorOf(R"({"map": "nowhere.hdr"})");
  EXPECT_NE(missing.find("scene.json: environment.map: "), std::string::npos) << missing;
  EXPECT_NE(missing.find("nowhere.hdr"), std::string::npos) << missing;

  std::ofstream(folder() / "broken.exr") << "not an exr";
  const std::string broken = environmentErrorOf(R"({"map": "broken.exr"})");
  EXPECT_NE(broken.find("environment.map: "), std::string::npos) << broken;
  EXPECT_NE(broken.find("broken.exr"), std::string::npos) << broken;

  std::ofstream(folder() / "sky.png") << "\x89PNG";
  const std::string png = environmentErrorOf(R"({"map": "sky.png"})");
  EXPECT_NE(png.find("sky.png: not a Radiance .hdr or OpenEXR .exr image"), std::string::npos) << png;
}

// scenes/sky: make_sky.py puts the sun 35 degrees up towards map -z; the scene turns the
// map 60 degrees about +y, which takes map -z to (-sin 60, 0, -cos 60).
TEST(EnvironmentScene, DemoSkyHasItsSunWhereTheScriptAndRotationPutIt) {
  const Scene scene = loadScene(test_support::sourceDir() / "scenes/sky/scene.json");
  const float up = std::sin(35 * static_cast<float>(M_PI) / 180), level = std::cos(35 * static_cast<float>(M_PI) / 180);
  const float s = std::sin(60 * static_cast<float>(M_PI) / 180), c = std::cos(60 * static_cast<float>(M_PI) / 180);
  EXPECT_NEAR(scene.environment.radiance({-level * s, up, -level * c}).r, 400, 1e-2);
  EXPECT_LT(scene.environment.radiance({level * s, up, level * c}).r, 1);
}

}  // namespace
}  // namespace pathfarm
