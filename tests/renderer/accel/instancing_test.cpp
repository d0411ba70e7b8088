// Objects that share a mesh, still or moving, are traced as Embree instances of one
// object-space BVH.
// Checked against the same scene with a private copy of the mesh per object (baked into
// world space, as before instancing): rays find the same surfaces, and the light sampler
// sees instanced emitters, mirrored ones included, as a ray does.
#include <gtest/gtest.h>

#include <cmath>

#include "renderer/accel/frame_geometry.h"
#include "renderer/integrators/frame_renderer.h"
#include "test_support.h"

namespace pathfarm {
namespace {

// Four boxes of one size (turned, stretched and moving, mirrored) on a floor, lit by two
// lamps of one size, the second mirrored; no sky.
Scene boxesAndLamps() {
  return test_support::sceneFromJson(R"({
    "render": {"resolution": [32, 32], "spp": 64, "max_depth": 4},
    "camera": {"position": [0, 3, 3], "look_at": [0, 0, 0], "fov": 50},
    "materials": {"white": {"type": "diffuse", "reflectance": 0.7},
                  "lamp": {"type": "diffuse", "reflectance": 0.5}},
    "shapes": [
      {"type": "rectangle", "size": [6, 6], "material": "white",
       "transform": {"rotate": {"axis": [1, 0, 0], "angle": -90}}},
      {"type": "box", "size": [0.5, 0.5, 0.5], "material": "white", "transform": {"translate": [-1, 0.25, 0]}},
      {"type": "box", "size": [0.5, 0.5, 0.5], "material": "white",
       "transform": {"translate": [0.8, 0.25, 0.3], "rotate": {"axis": [0, 1, 0], "angle": 30}}},
      {"type": "box", "size": [0.5, 0.5, 0.5], "material": "white",
       "transform": {"translate": [0, 0.5, -1], "scale": [0.5, 2, 1.5]},
       "animation": {"translate": [{"frame": 0, "value": [0, 0.5, -1]}, {"frame": 4, "value": [0.4, 0.5, -1.2]}]}},
      {"type": "box", "size": [0.5, 0.5, 0.5], "material": "white",
       "transform": {"translate": [0.2, 0.2, 1], "rotate": {"axis": [1, 1, 0], "angle": 20}, "scale": [-1, 0.8, 1]}},
      {"type": "rectangle", "size": [0.6, 0.6], "material": "lamp", "emission": [8, 6, 4],
       "transform": {"translate": [-0.7, 1.8, 0.4], "rotate": {"axis": [1, 0, 0], "angle": 90}}},
      {"type": "rectangle", "size": [0.6, 0.6], "material": "lamp", "emission": [8, 6, 4],
       "transform": {"translate": [0.9, 1.6, -0.3], "rotate": {"axis": [1, 0, 0], "angle": -90}, "scale": [1.5, 1, -1]}}
    ]})");
}

// The same scene with every box placing the first box's mesh and every lamp the first lamp's.
Scene sharingMeshes(Scene scene) {
  for (const size_t box : {2, 3, 4}) scene.objects[box].mesh = scene.objects[1].mesh;
  scene.objects[6].mesh = scene.objects[5].mesh;
  return scene;
}

TEST(Instancing, SharedStaticMeshesShareOneBvh) {
  const Scene copies = boxesAndLamps();
  const Scene shared = sharingMeshes(copies);
  const EmbreeDevice device;
  const ShotGeometry copied(copies, device), instanced(shared, device);
  for (int object = 0; object < 7; ++object) EXPECT_FALSE(copied.shape(object).instanced) << object;
  EXPECT_FALSE(instanced.shape(0).instanced);  // the floor's mesh is its own
  for (int object = 1; object < 7; ++object)
    EXPECT_EQ(instanced.shape(object).instanced, object != 3) << object;  // box 3 moves: placed per frame
  EXPECT_TRUE(instanced.shape(3).animated);
  for (const int box : {2, 3, 4}) {
    EXPECT_EQ(instanced.objectScene(box), instanced.objectScene(1));
    EXPECT_EQ(instanced.shape(box).mesh, instanced.shape(1).mesh);
  }
  EXPECT_EQ(instanced.objectScene(6), instanced.objectScene(5));
  EXPECT_NE(instanced.objectScene(5), instanced.objectScene(1));
  // The bounds the environment's share of power is computed from cover the instances.
  const RTCBounds& a = copied.staticBounds();
  const RTCBounds& b = instanced.staticBounds();
  for (const auto& [x, y] : {std::pair{a.lower_x, b.lower_x}, {a.upper_x, b.upper_x}, {a.lower_y, b.lower_y},
                             {a.upper_y, b.upper_y}, {a.lower_z, b.lower_z}, {a.upper_z, b.upper_z}})
    EXPECT_NEAR(x, y, 1e-4f);
}

TEST(Instancing, RaysFindWhatWorldSpaceCopiesShow) {
  const Scene copies = boxesAndLamps();
  const Scene shared = sharingMeshes(copies);
  const EmbreeDevice device;
  const ShotGeometry copiedShot(copies, device), instancedShot(shared, device);
  const FrameGeometry copied(copiedShot, 0), instanced(instancedShot, 0);
  int rays = 0, hits = 0, disagreements = 0;
  for (int i = 0; i < 64; ++i)
    for (int j = 0; j < 64; ++j)
      for (const float height : {0.3f, 2.5f}) {
        // From around the scene towards points near the origin, grazing and steep.
        const Vec3f origin{3 * std::cos(0.1f * i), height, 3 * std::sin(0.1f * i)};
        const Vec3f target{(j % 8) * 0.3f - 1.1f, 0.3f, (j / 8) * 0.3f - 1.1f};
        const Ray ray{origin, normalize(target - origin)};
        SurfaceHit a, b;
        const bool foundA = copied.intersect(ray, 0.5f, a), foundB = instanced.intersect(ray, 0.5f, b);
        ++rays;
        if (!foundA && !foundB) continue;
        ++hits;
        // A ray through an edge may round to either side of it.
        if (foundA != foundB || a.object != b.object || std::abs(a.distance - b.distance) > 1e-4f * a.distance) {
          ++disagreements;
          continue;
        }
        test_support::expectNear(a.position, b.position, 1e-4f);
        test_support::expectNear(a.geometricNormal, b.geometricNormal, 1e-4f);
        test_support::expectNear(a.shadingNormal, b.shadingNormal, 1e-4f);
        EXPECT_NEAR(a.uv.x, b.uv.x, 1e-4f);
        EXPECT_NEAR(a.uv.y, b.uv.y, 1e-4f);
        // Motion and re-projection read the object-space point through shapeToWorld.
        test_support::expectNear(instanced.shapeToWorld(b.object, 0.5f).point(b.shapePosition), b.position, 1e-4f);
      }
  EXPECT_GT(hits, rays / 2);
  EXPECT_LE(disagreements, hits / 1000) << "of " << hits << " hits";
}

TEST(Instancing, InstancedLampsLightTheSceneAsCopiesDo) {
  const Scene copies = boxesAndLamps();
  const Scene shared = sharingMeshes(copies);
  const FrameImage a = FrameRenderer(copies, RenderSettings::defaultsOf(copies)).render(0);
  const FrameImage b = FrameRenderer(shared, RenderSettings::defaultsOf(shared)).render(0);
  // Both estimate the same image. Light samples on the mirrored lamp land elsewhere (its
  // world-space copy had its winding flipped), so the two are compared as independent
  // estimates: each 8 x 8 block's means within 4 standard errors of their difference.
  // A lamp lit on the wrong side, or sampled with another density, moves whole regions.
  for (const char* channel : {"R", "G", "B"}) {
    EXPECT_GT(test_support::meanOverPixels(a, channel).mean, 0.05) << channel;
    const auto& va = a.channel(channel);
    const auto& vb = b.channel(channel);
    const auto& variance = a.channel(std::string("variance.") + channel);
    const auto& varianceB = b.channel(std::string("variance.") + channel);
    for (int by = 0; by < 32; by += 8)
      for (int bx = 0; bx < 32; bx += 8) {
        double difference = 0, differenceVariance = 0;
        for (int y = by; y < by + 8; ++y)
          for (int x = bx; x < bx + 8; ++x) {
            const size_t p = static_cast<size_t>(y) * 32 + static_cast<size_t>(x);
            difference += va[p] - vb[p];
            differenceVariance += variance[p] + varianceB[p];
          }
        EXPECT_LT(std::abs(difference), 4 * std::sqrt(differenceVariance) + 1e-6)
            << channel << " block " << bx << ", " << by;
      }
  }
}

}  // namespace
}  // namespace pathfarm
