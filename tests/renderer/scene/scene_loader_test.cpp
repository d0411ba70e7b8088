// Scene files: the demo scenes load, every kind of bad input names the file and key,
// and no mangled file crashes the loader.
#include <gtest/gtest.h>

#include <fstream>
#include <random>

#include "renderer/scene/scene_loader.h"
#include "test_support.h"

namespace pathfarm {
namespace {

const char* kValid = R"({
  "fps": 24,
  "render": {"resolution": [64, 48], "spp": 4, "max_depth": 5, "frames": [0, 3]},
  "camera": {"position": [0, 1, 4], "look_at": [0, 1, 0], "fov": 40},
  "materials": {"white": {"type": "diffuse", "reflectance": [0.7, 0.7, 0.7]},
                "gold": {"type": "rough_conductor", "alpha": 0.2, "eta": [0.14, 0.37, 1.44], "k": [3.98, 2.38, 1.6]},
                "glass": {"type": "dielectric", "ior": 1.5}},
  "shapes": [
    {"type": "rectangle", "size": [4, 4], "material": "white", "object_id": 7},
    {"type": "sphere", "radius": 0.5, "material": "gold", "transform": {"translate": [0, 0.5, 0]}},
    {"type": "box", "size": [1, 1, 1], "material": "glass", "emission": [1, 2, 3]}
  ]
})";

std::string loaderErrorOf(const std::string& json) {
  return test_support::sceneErrorOf([&] { test_support::sceneFromJson(json, "/scenes"); });
}

// `replace` swaps the first occurrence of `from` in the valid scene for `to`.
std::string mutated(const std::string& from, const std::string& to) {
  std::string text = kValid;
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(SceneLoader, LoadsTheDemoScenes) {
  for (const char* path : {"scenes/cornell/scene.json", "scenes/materials/scene.json"}) {
    const Scene scene = loadScene(test_support::sourceDir() / path);
    EXPECT_FALSE(scene.objects.empty()) << path;
  }
  const Scene cornell = loadScene(test_support::sourceDir() / "scenes/cornell/scene.json");
  EXPECT_EQ(cornell.defaults.frameEnd - cornell.defaults.frameStart + 1, 24);
}

TEST(SceneLoader, ReadsTheValidScene) {
  const Scene scene = test_support::sceneFromJson(kValid, "/scenes");
  EXPECT_EQ(scene.defaults.width, 64);
  EXPECT_EQ(scene.defaults.maxDepth, 5);
  ASSERT_EQ(scene.objects.size(), 3u);
  EXPECT_EQ(scene.objects[0].objectId, 7u);
  EXPECT_EQ(scene.objects[1].objectId, 2u);  // default: position in the list, from 1
  EXPECT_EQ(scene.materials[static_cast<size_t>(scene.objects[1].material)].type, MaterialType::RoughConductor);
  EXPECT_FLOAT_EQ(scene.objects[2].emission.b, 3.0f);
  EXPECT_FLOAT_EQ(scene.camera.focusDistance, 4.0f);
}

TEST(SceneLoader, EachBadInputNamesFileAndKey) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {mutated(R"("material": "gold")", R"("material": "glas")"),
       R"(/scenes/scene.json: shapes[1].material: unknown material "glas")"},
      {mutated(R"("type": "sphere")", R"("type": "cone")"), R"(shapes[1].type: unknown shape type "cone")"},
      {mutated(R"("type": "dielectric")", R"("type": "glass")"), R"(materials.glass.type: unknown material type "glass")"},
      {mutated(R"("radius": 0.5)", R"("radius": -0.5)"), "shapes[1].radius: -0.5 is out of range"},
      {mutated(R"("radius": 0.5)", R"("radius": "big")"), "shapes[1].radius: expected a number, found a string"},
      {mutated(R"("radius": 0.5, )", ""), R"(shapes[1]: missing key "radius")"},
      {mutated(R"("fov": 40)", R"("fov": 40, "zoom": 2)"), "camera.zoom: unknown key"},
      {mutated(R"("look_at": [0, 1, 0])", R"("look_at": [0, 1])"), "camera.look_at: expected an array of 3 numbers"},
      {mutated(R"("look_at": [0, 1, 0])", R"("look_at": [0, 1, 4])"), "camera.look_at: look_at must differ from position"},
      {mutated(R"("ior": 1.5)", R"("ior": 0.5)"), "materials.glass.ior: 0.5 is out of range"},
      {mutated(R"("alpha": 0.2, )", R"("alpha": 0.2, "ior": 1.5, )"), "materials.gold.ior: unknown key (expected one of: type, alpha"},
      {mutated(R"("k": [3.98, 2.38, 1.6])", R"("kk": 1)"), "materials.gold.kk: unknown key"},
      {mutated(R"("reflectance": [0.7, 0.7, 0.7])", R"("reflectance": [0.7, 1.7, 0.7])"), "materials.white.reflectance[1]: 1.7 is out of range [0, 1]"},
      {mutated(R"("object_id": 7)", R"("object_id": 2)"), "shapes[1]: object id 2 is used twice"},
      {mutated(R"("resolution": [64, 48])", R"("resolution": [64, 0])"), "render.resolution[1]: 0 is out of range"},
      {mutated(R"("frames": [0, 3])", R"("frames": [3, 0])"), "render.frames[1]: 0 is out of range"},
      {mutated(R"("spp": 4)", R"("spp": 4.5)"), "render.spp: expected a whole number"},
      {mutated(R"("transform": {"translate": [0, 0.5, 0]})", R"("transform": {"scale": [1, 2, 1]})"),
       "shapes[1]: a sphere can only be scaled uniformly"},
      {mutated(R"("size": [1, 1, 1])", R"("size": [1, 1, 1], "animation": {"rotate": [{"time": 1, "axis": [0, 1, 0], "angle": 5}, {"time": 0, "axis": [0, 1, 0], "angle": 9}]})"),
       "shapes[2].animation.rotate[1]: key times must increase strictly"},
      {mutated(R"("type": "box", "size": [1, 1, 1])", R"("type": "mesh", "file": "missing.obj")"),
       "shapes[2].file: /scenes/missing.obj"},
      {mutated(R"("type": "diffuse", "reflectance": [0.7, 0.7, 0.7])", R"("type": "diffuse", "reflectance": {"texture": "nope.png"})"),
       "materials.white.reflectance.texture: /scenes/nope.png"},
      {R"({"camera": {"position": [0, 0, 1], "look_at": [0, 0, 0]}, "materials": {}, "shapes": []})",
       "shapes: a scene needs at least one shape"},
      {R"([1, 2])", "(top level): expected an object, found an array"},
      {R"({"camera": )", "/scenes/scene.json: invalid JSON"},
      {mutated(R"("spp": 4)", R"("spp": 1e400)"), "/scenes/scene.json: invalid JSON"},  // beyond double
  };
  for (const auto& [json, expected] : cases) {
    const std::string message = loaderErrorOf(json);
    EXPECT_NE(message.find(expected), std::string::npos) << "expected \"" << expected << "\" in \"" << message << "\"";
  }
}

TEST(SceneLoader, MissingFileIsAnError) {
  try {
    loadScene("/nonexistent/scene.json");
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/scene.json: cannot open"), std::string::npos);
  }
}

// Random edits of a valid scene either load or throw SceneError: never a crash, a hang
// or another exception.
TEST(SceneLoader, MangledFilesNeverCrash) {
  std::mt19937 random(1234);
  const std::string valid = kValid;
  int rejected = 0;
  for (int iteration = 0; iteration < 3000; ++iteration) {
    std::string text = valid;
    const int edits = 1 + static_cast<int>(random() % 4);
    for (int e = 0; e < edits && !text.empty(); ++e) {
      const size_t at = random() % text.size();
      switch (random() % 4) {
        case 0: text.resize(at); break;                                            // truncate
        case 1: text[at] = static_cast<char>(random() % 128); break;               // overwrite
        case 2: text.erase(at, 1 + random() % 8); break;                           // delete
        default: text.insert(at, 1, "{}[],:\"0123456789-e.ntf"[random() % 23]);    // insert
      }
    }
    try {
      test_support::sceneFromJson(text, "/scenes");
    } catch (const SceneError&) {
      ++rejected;
    } catch (const std::exception& e) {
      FAIL() << "unexpected " << typeid(e).name() << ": " << e.what() << "\nfor input:\n" << text;
    }
  }
  EXPECT_GT(rejected, 2000);  // almost every edit must be noticed
}

}  // namespace
}  // namespace pathfarm
