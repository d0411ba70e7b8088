// KHR_lights_punctual: lights placed and animated by their nodes arrive in the scene with
// the file's colour, intensity (candela and lux, turned into watts at 683 lm/W) and cones;
// a light a node refers to wrongly is refused by pointer; and a glTF point light lights a
// floor as its closed form says.
#include <gtest/gtest.h>

#include <cmath>

#include "renderer/integrators/frame_renderer.h"
#include "renderer/scene/scene_loader.h"
#include "test_support.h"
#include "tests/renderer/lights/lit_floor.h"
#include "tests/renderer/scene/gltf/gltf_builder.h"

namespace pathfarm {
namespace {

using gltftest::GltfBuilder;
using test_support::expectNear;

std::filesystem::path lightsFolder() { return test_support::processTemporaryFolder("pathfarm_gltf_lights"); }

const float kHalfTurn = std::sqrt(0.5f);  // sin and cos of 45 degrees, for quarter-turn quaternions
const float kLumensPerWatt = 683;  // the luminous efficacy the extension's units assume

// A point light (colour (1, 0.5, 0.25), 4 cd), a spot (10 cd, cones 0.2 and 0.5 rad) and
// a directional light (3 lux), each on its own node.
GltfBuilder threeLights() {
  GltfBuilder b;
  b.doc()["extensionsUsed"] = {"KHR_lights_punctual"};
  b.doc()["extensions"]["KHR_lights_punctual"]["lights"] = {
      {{"type", "point"}, {"color", {1, 0.5, 0.25}}, {"intensity", 4}, {"name", "bulb"}},
      {{"type", "spot"}, {"intensity", 10}, {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.5}}}},
      {{"type", "directional"}, {"intensity", 3}}};
  return b;
}

nlohmann::json lightRef(int light) { return {{"KHR_lights_punctual", {{"light", light}}}}; }

TEST(GltfLights, NodesPlaceLightsWithTheFilesColourIntensityAndCones) {
  GltfBuilder b = threeLights();
  const int point = b.node({{"extensions", lightRef(0)}, {"translation", {1, 2, 3}}});
  // Turned -90 degrees about x: the spot's -z points down -y.
  const int spot = b.node({{"name", "key"}, {"extensions", lightRef(1)}, {"rotation", {-kHalfTurn, 0, 0, kHalfTurn}}});
  const int sun = b.node({{"extensions", lightRef(2)}});
  b.scene({b.node({{"mesh", b.square()}}), b.camera({0, 0, 3}), point, spot, sun});
  const Scene scene = loadScene(b.write(lightsFolder(), "three"));
  ASSERT_EQ(scene.punctualLights.size(), 3u);
  const PunctualLight& bulb = scene.punctualLights[0];
  EXPECT_EQ(bulb.type, PunctualType::Point);
  EXPECT_EQ(bulb.name, "bulb");  // the node has no name: the light's
  EXPECT_FLOAT_EQ(bulb.intensity.r, 4 / kLumensPerWatt);
  EXPECT_FLOAT_EQ(bulb.intensity.g, 2 / kLumensPerWatt);
  EXPECT_FLOAT_EQ(bulb.intensity.b, 1 / kLumensPerWatt);
  expectNear(bulb.position(0), {1, 2, 3});
  const PunctualLight& key = scene.punctualLights[1];
  EXPECT_EQ(key.type, PunctualType::Spot);
  EXPECT_EQ(key.name, "key");
  EXPECT_FLOAT_EQ(key.cosInner, std::cos(0.2f));
  EXPECT_FLOAT_EQ(key.cosOuter, std::cos(0.5f));
  EXPECT_FLOAT_EQ(key.intensity.g, 10 / kLumensPerWatt);
  expectNear(key.forward(0), {0, -1, 0}, 1e-6f);
  EXPECT_EQ(scene.punctualLights[2].type, PunctualType::Directional);
  EXPECT_FLOAT_EQ(scene.punctualLights[2].intensity.g, 3 / kLumensPerWatt);
  expectNear(scene.punctualLights[2].forward(0), {0, 0, -1});
}

// The sun hangs under a parent turning 90 degrees about +y over 1 s (LINEAR): its -z
// swings from -z to -x, through the diagonal at 0.5 s.
TEST(GltfLights, AnAnimatedParentTurnsItsLight) {
  GltfBuilder b = threeLights();
  const int sun = b.node({{"extensions", lightRef(2)}});
  const int parent = b.node({{"children", {sun}}});
  b.scene({b.node({{"mesh", b.square()}}), b.camera({0, 0, 3}), parent});
  const int input = b.floats({0, 1}, "SCALAR");
  const int output = b.floats({0, 0, 0, 1, 0, kHalfTurn, 0, kHalfTurn}, "VEC4");
  b.doc()["animations"] = {{{"samplers", {{{"input", input}, {"output", output}}}},
                            {"channels", {{{"sampler", 0}, {"target", {{"node", parent}, {"path", "rotation"}}}}}}}};
  const Scene scene = loadScene(b.write(lightsFolder(), "turning"));
  ASSERT_EQ(scene.punctualLights.size(), 1u);
  const PunctualLight& light = scene.punctualLights[0];
  EXPECT_TRUE(light.transform.isAnimated());
  expectNear(light.forward(0), {0, 0, -1}, 1e-5f);
  expectNear(light.forward(0.5), {-kHalfTurn, 0, -kHalfTurn}, 1e-4f);
  expectNear(light.forward(1), {-1, 0, 0}, 1e-5f);
}

std::string lightsLoadError(GltfBuilder& b, const std::string& name) {
  return test_support::sceneErrorOf([&] { loadScene(b.write(lightsFolder(), name)); });
}

TEST(GltfLights, BadLightsAreRefusedByPointer) {
  {
    GltfBuilder b = threeLights();
    b.scene({b.node({{"mesh", b.square()}}), b.camera({0, 0, 3}), b.node({{"extensions", lightRef(7)}})});
    EXPECT_NE(lightsLoadError(b, "missing").find("/nodes/2/extensions/KHR_lights_punctual/light"), std::string::npos);
  }
  {
    GltfBuilder b = threeLights();
    b.doc()["extensions"]["KHR_lights_punctual"]["lights"][1]["spot"]["innerConeAngle"] = 0.6;
    b.scene({b.node({{"mesh", b.square()}}), b.camera({0, 0, 3}), b.node({{"extensions", lightRef(1)}})});
    EXPECT_NE(lightsLoadError(b, "cones").find("/extensions/KHR_lights_punctual/lights/1/spot"), std::string::npos);
  }
  {
    GltfBuilder b = threeLights();
    b.doc()["extensions"]["KHR_lights_punctual"]["lights"][0]["type"] = "area";
    b.scene({b.node({{"mesh", b.square()}}), b.camera({0, 0, 3}), b.node({{"extensions", lightRef(0)}})});
    EXPECT_NE(lightsLoadError(b, "type").find("/extensions/KHR_lights_punctual/lights/0/type"), std::string::npos);
  }
  {
    GltfBuilder b = threeLights();
    b.doc()["extensions"]["KHR_lights_punctual"]["lights"][0]["intensity"] = -2;
    b.scene({b.node({{"mesh", b.square()}}), b.camera({0, 0, 3}), b.node({{"extensions", lightRef(0)}})});
    EXPECT_NE(lightsLoadError(b, "negative").find("/extensions/KHR_lights_punctual/lights/0/intensity"), std::string::npos);
  }
  {
    // Required, the extension is implemented, so the file loads.
    GltfBuilder b = threeLights();
    b.doc()["extensionsRequired"] = {"KHR_lights_punctual"};
    b.scene({b.node({{"mesh", b.square()}}), b.camera({0, 0, 3}), b.node({{"extensions", lightRef(0)}})});
    EXPECT_EQ(lightsLoadError(b, "required"), "(no error)");
  }
}

// A floor (the unit square scaled 100) seen from 2 above by a camera whose view spans
// |x|, |y| <= 1 on it, lit by the file's point light (green 683 cd, which is 1 W/sr) at
// (0.3, 0.2, 1), its material replaced by a Lambertian of albedo 1/2 through a JSON include.
TEST(GltfLights, APointLightFromTheFileLightsTheFloorAsTheClosedFormSays) {
  GltfBuilder b;
  b.doc()["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"color", {1, 0.5, 0.25}}, {"intensity", 2 * kLumensPerWatt}}};
  b.doc()["materials"] = {{{"name", "floor"}}};
  const int floor = b.node({{"mesh", b.square(0)}, {"scale", {100, 100, 1}}});
  const int light = b.node({{"extensions", lightRef(0)}, {"translation", {0.3, 0.2, 1}}});
  b.scene({floor, light, b.camera({0, 0, 2}, 2 * std::atan(0.5))});
  b.write(lightsFolder(), "lit");
  const Scene scene = parseScene(R"({
    "include": "lit.gltf", "render": {"resolution": [16, 16], "spp": 16, "max_depth": 2},
    "materials": {"floor": {"type": "diffuse", "reflectance": 0.5}}})", lightsFolder() / "shot.json");
  const auto estimate = test_support::meanOverPixels(FrameRenderer(scene, RenderSettings::defaultsOf(scene)).render(0), "G");
  const double reference = test_support::meanOverSquare(
      1, [](double x, double y) { return test_support::pointLitRadiance(0.5, x, y, 0.3, 1, 0.2, 1); });
  EXPECT_NEAR(estimate.mean, reference, 4 * estimate.standardError + 1e-6);
  EXPECT_GT(reference, 0.05);
}

// An including JSON file replaces a glTF light by name and adds its own.
TEST(GltfLights, JsonIncludesReplaceLightsByNameAndAddTheirOwn) {
  GltfBuilder b = threeLights();
  b.scene({b.node({{"mesh", b.square()}}), b.camera({0, 0, 3}), b.node({{"extensions", lightRef(0)}})});
  b.write(lightsFolder(), "replaced");
  const Scene scene = parseScene(R"({"include": "replaced.gltf", "lights": [
    {"name": "bulb", "type": "spot", "position": [0, 0, 1], "intensity": 7},
    {"type": "directional", "intensity": 1}]})", lightsFolder() / "replacing.json");
  ASSERT_EQ(scene.punctualLights.size(), 2u);
  EXPECT_EQ(scene.punctualLights[0].type, PunctualType::Spot);
  EXPECT_FLOAT_EQ(scene.punctualLights[0].intensity.g, 7);
  EXPECT_EQ(scene.punctualLights[1].type, PunctualType::Directional);
}

}  // namespace
}  // namespace pathfarm
