// Normal maps bend the shading normal as glTF's tangent-space convention says: red along
// the tangent (increasing u), green along the bitangent (up in the image), blue along
// the surface normal; with the mesh's TANGENT or with the frame of its uvs.
#include <gtest/gtest.h>
#include <stb_image_write.h>

#include <cmath>

#include "renderer/accel/embree_device.h"
#include "renderer/accel/frame_geometry.h"
#include "renderer/scene/scene_loader.h"
#include "test_support.h"
#include "tests/renderer/scene/gltf/gltf_builder.h"

namespace pathfarm {
namespace {

using gltftest::GltfBuilder;
using test_support::expectNear;

std::filesystem::path normalMapFolder() { return test_support::processTemporaryFolder("pathfarm_gltf_normal_map"); }

// One texel (204, 128, 230): tangent-space (2 * 204/255 - 1, 2 * 128/255 - 1,
// 2 * 230/255 - 1) = (0.6, 0.0039, 0.8039) before scaling.
constexpr unsigned char kTexel[] = {204, 128, 230};

Vec3f expectedNormal(Vec3f tangent, Vec3f bitangent, Vec3f normal, float scale) {
  const float x = (2 * 204 / 255.0f - 1) * scale, y = (2 * 128 / 255.0f - 1) * scale, z = 2 * 230 / 255.0f - 1;
  return normalize(tangent * x + bitangent * y + normal * z);
}

// Each test writes its own image: ctest runs the tests as parallel processes.
GltfBuilder normalMappedSquare(float scale, const std::string& name) {
  std::filesystem::create_directories(normalMapFolder());
  const std::string image = name + "_bump.png";
  EXPECT_NE(stbi_write_png((normalMapFolder() / image).c_str(), 1, 1, 3, kTexel, 3), 0);
  GltfBuilder b;
  b.doc()["images"] = {{{"uri", image}}};
  b.doc()["textures"] = {{{"source", 0}}};
  b.doc()["materials"] = {{{"normalTexture", {{"index", 0}, {"scale", scale}}}}};
  return b;
}

// The shading normal where a ray down -z from (0.2, 0.3, 5) meets the scene at time 0.
Vec3f shadingNormalAtCentre(const Scene& scene) {
  EmbreeDevice device;
  const ShotGeometry shot(scene, device);
  const FrameGeometry frame(shot, 0);
  SurfaceHit hit;
  EXPECT_TRUE(frame.intersect({{0.2f, 0.3f, 5}, {0, 0, -1}}, 0, hit));
  return hit.shadingNormal;
}

TEST(GltfNormalMap, UvFrameBendsTheNormalTowardsTangentAndBitangent) {
  GltfBuilder b = normalMappedSquare(0.5f, "uv_frame");
  // The square's u grows along +x and its image-up (v in pathfarm) along +y.
  b.scene({b.node({{"mesh", b.square(0)}}), b.camera({0, 0, 5})});
  const Scene scene = loadScene(b.write(normalMapFolder(), "uv_frame"));
  expectNear(shadingNormalAtCentre(scene), expectedNormal({1, 0, 0}, {0, 1, 0}, {0, 0, 1}, 0.5f), 1e-4f);
}

TEST(GltfNormalMap, MeshTangentsAndAQuarterTurnMoveTheBendWithTheSurface) {
  GltfBuilder b = normalMappedSquare(1.0f, "tangents");
  // The same square with TANGENT = +y and handedness -1 (bitangent = cross(+z, +y) * -1
  // = +x), turned a quarter about z: tangent -> -x, bitangent -> +y.
  const int position = b.floats({-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0}, "VEC3", true);
  const int normal = b.floats({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
  const int tangent = b.floats({0, 1, 0, -1, 0, 1, 0, -1, 0, 1, 0, -1, 0, 1, 0, -1}, "VEC4");
  const int uv = b.floats({0, 1, 1, 1, 1, 0, 0, 0}, "VEC2");
  const int mesh = b.mesh({{"POSITION", position}, {"NORMAL", normal}, {"TANGENT", tangent}, {"TEXCOORD_0", uv}},
                          b.indices(std::vector<uint16_t>{0, 1, 2, 0, 2, 3}), 0);
  const float s = std::sqrt(0.5f);
  b.scene({b.node({{"mesh", mesh}, {"rotation", {0, 0, s, s}}}), b.camera({0, 0, 5})});
  const Scene scene = loadScene(b.write(normalMapFolder(), "tangents"));
  expectNear(shadingNormalAtCentre(scene), expectedNormal({-1, 0, 0}, {0, 1, 0}, {0, 0, 1}, 1.0f), 1e-4f);
}

TEST(GltfNormalMap, AMirroredAnimatedSquareKeepsTheBendOnTheMirroredSide) {
  GltfBuilder b = normalMappedSquare(1.0f, "mirrored");
  // Mirrored in x (scale -1, 1, 1) and moving: the uv frame's u now grows along -x.
  const int node = b.node({{"mesh", b.square(0)}, {"scale", {-1, 1, 1}}});
  b.scene({node, b.camera({0, 0, 5})});
  const int input = b.floats({0, 1}, "SCALAR");
  const int output = b.floats({0, 0, 0, 0, 0, -1}, "VEC3");
  b.doc()["animations"] = {{{"samplers", {{{"input", input}, {"output", output}}}},
                            {"channels", {{{"sampler", 0}, {"target", {{"node", node}, {"path", "translation"}}}}}}}};
  const Scene scene = loadScene(b.write(normalMapFolder(), "mirrored"));
  ASSERT_TRUE(scene.objects[0].transform.isAnimated());
  expectNear(shadingNormalAtCentre(scene), expectedNormal({-1, 0, 0}, {0, 1, 0}, {0, 0, 1}, 1.0f), 1e-4f);
}

TEST(GltfNormalMap, ADegenerateTangentIsRefused) {
  GltfBuilder b = normalMappedSquare(1.0f, "zero_tangent");
  const int position = b.floats({-1, -1, 0, 1, -1, 0, 1, 1, 0}, "VEC3", true);
  const int normal = b.floats({0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
  const int tangent = b.floats({1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 0, 1}, "VEC4");
  b.scene({b.node({{"mesh", b.mesh({{"POSITION", position}, {"NORMAL", normal}, {"TANGENT", tangent}})}}),
           b.camera({0, 0, 5})});
  try {
    loadScene(b.write(normalMapFolder(), "zero_tangent"));
    FAIL() << "expected a SceneError";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("/attributes/TANGENT"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pathfarm
