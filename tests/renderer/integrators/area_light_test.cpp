// Direct lighting from a rectangular area light onto a diffuse plane, against the closed
// form of Lambert's polygon formula evaluated independently here.
#include <gtest/gtest.h>

#include <array>

#include "renderer/accel/frame_geometry.h"
#include "renderer/integrators/path_tracer.h"
#include "renderer/integrators/light_sampler.h"
#include "test_support.h"

namespace pathfarm {
namespace {

// Irradiance at p (normal n) from a uniform Lambertian polygon of radiance Le:
// E = Le / 2 * sum over edges of angle(v_i, v_i+1) * n . unit(v_i x v_i+1), with the
// polygon's vertices seen from p (Lambert 1760; see Arvo 1995).
double polygonIrradiance(Vec3f p, Vec3f n, const std::array<Vec3f, 4>& polygon, double radiance) {
  double sum = 0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Vec3f a = normalize(polygon[i] - p), b = normalize(polygon[(i + 1) % polygon.size()] - p);
    const double angle = std::acos(std::clamp(static_cast<double>(dot(a, b)), -1.0, 1.0));
    sum += angle * dot(n, normalize(cross(a, b)));
  }
  return radiance * 0.5 * std::abs(sum);
}

TEST(AreaLight, DiffusePlaneMatchesLambertsFormula) {
  const float albedo = 0.8f, emission = 5.0f, height = 1.0f;
  const Scene scene = test_support::sceneFromJson(R"({
    "camera": {"position": [0, 3, 3], "look_at": [0, 0, 0]},
    "materials": {"plane": {"type": "diffuse", "reflectance": 0.8},
                  "black": {"type": "diffuse", "reflectance": 0}},
    "shapes": [
      {"type": "rectangle", "size": [20, 20], "material": "plane",
       "transform": {"rotate": {"axis": [1, 0, 0], "angle": -90}}},
      {"type": "rectangle", "size": [0.6, 0.4], "material": "black", "emission": 5,
       "transform": {"translate": [0.1, 1, 0.2], "rotate": {"axis": [1, 0, 0], "angle": 90}}}]
  })");
  // The light's corners in world space: centered at (0.1, 1, 0.2), 0.6 along x, 0.4 along z.
  const std::array<Vec3f, 4> light{Vec3f{-0.2f, height, 0.0f}, Vec3f{0.4f, height, 0.0f},
                                   Vec3f{0.4f, height, 0.4f}, Vec3f{-0.2f, height, 0.4f}};
  EmbreeDevice device;
  const ShotGeometry shot(scene, device);
  const FrameGeometry geometry(shot, 0);
  const LightSampler lights(shot);
  const PathTracer tracer(geometry, lights, {.maxDepth = 1});

  // Under the light's center, under a corner, and well outside its footprint.
  for (const Vec3f target : {Vec3f{0.1f, 0, 0.2f}, Vec3f{0.4f, 0, 0.0f}, Vec3f{1.5f, 0, -1.0f}}) {
    const Vec3f origin = target + normalize(Vec3f{0.5f, 0.2f, 0.3f}) * 0.3f;
    const Ray ray{origin, normalize(target - origin)};
    const int n = 20000;
    double sum = 0, sumSquares = 0;
    RayCounts counts;
    for (int s = 0; s < n; ++s) {
      SampleStream stream({1, 0, 0, 0, static_cast<uint32_t>(s)});
      const double value = tracer.radiance(ray, 0, stream, counts).g;
      sum += value;
      sumSquares += value * value;
    }
    const double mean = sum / n;
    const double standardError = std::sqrt((sumSquares / n - mean * mean) / (n - 1));
    const double expected = albedo / kPi * polygonIrradiance(target, {0, 1, 0}, light, emission);
    EXPECT_NEAR(mean, expected, 3 * standardError + 1e-6)
        << "at (" << target.x << ", " << target.z << "), expected " << expected;
  }
}

}  // namespace
}  // namespace pathfarm
