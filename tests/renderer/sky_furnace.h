#pragma once
// The sky furnace: a diffuse sphere of albedo 0.5 in a constant environment ("sky") of
// radiance 1. A convex diffuse object in a uniform sky never sees itself and reflects
// exactly albedo x sky, so every integrator's frame must read 0.5 on the sphere's pixels
// and 1.0 on the sky's. Pixels that the sphere's silhouette crosses belong to neither.
#include <cmath>
#include <string>
#include <vector>

#include "image/frame_image.h"
#include "test_support.h"
#include "tests/renderer/sky_map.h"

namespace pathfarm::test_support {

constexpr double kSkyFurnaceSphere = 0.5, kSkyFurnaceSky = 1.0;

// Where the sky comes from: a constant radiance, or a map file whose texels are all 2
// at strength 1/2 (sky_map.h), which takes every integrator through the map's lookups and
// importance sampling while the answer stays the same.
enum class SkySource { Radiance, ConstantMap };

// The unit sphere seen from 5 away with a 30 degree field of view: it covers about 45 %
// of a square frame. The shutter [0, 0.5] is what the Metropolis integrators sample.
inline Scene skyFurnaceScene(uint64_t seed = 0, SkySource sky = SkySource::Radiance) {
  const std::string environment = sky == SkySource::Radiance
                                      ? R"({"radiance": 1})"
                                      : R"({"map": ")" + constantSkyMap(2).string() + R"(", "strength": 0.5})";
  Scene scene = sceneFromJson(R"({
    "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov": 30, "shutter": [0, 0.5]},
    "materials": {"m": {"type": "diffuse", "reflectance": 0.5}},
    "environment": )" + environment + R"(,
    "shapes": [{"type": "sphere", "radius": 1, "material": "m"}]
  })");
  scene.seed = seed;
  return scene;
}

enum class SkyRegion { Sphere, Sky, Silhouette };

// Where pixel (x, y) of a width x height frame of the furnace lies. On the image plane at
// distance 1 the silhouette is the circle of radius tan(asin(1 / 5)) = 1 / sqrt(24)
// around the frame's centre; a pixel is the sphere's (the sky's) when its whole square
// lies inside (outside) it.
inline SkyRegion skyRegionOf(int x, int y, int width, int height) {
  const double tanHalfFov = std::tan(15.0 * M_PI / 180.0);
  const double pixel = 2 * tanHalfFov / height;  // square pixels, the field of view vertical
  const double x0 = (x - 0.5 * width) * pixel, x1 = x0 + pixel;
  const double y0 = (y - 0.5 * height) * pixel, y1 = y0 + pixel;
  const auto nearest = [](double lo, double hi) { return lo > 0 ? lo : hi < 0 ? hi : 0.0; };
  const double nx = nearest(x0, x1), ny = nearest(y0, y1);
  const double fx = std::max(std::abs(x0), std::abs(x1)), fy = std::max(std::abs(y0), std::abs(y1));
  const double radiusSquared = 1.0 / 24.0;
  if (fx * fx + fy * fy < radiusSquared) return SkyRegion::Sphere;
  if (nx * nx + ny * ny > radiusSquared) return SkyRegion::Sky;
  return SkyRegion::Silhouette;
}

struct SkyFurnaceMeans {
  MeanEstimate sphere, sky;
};

// The mean of `values` (one per pixel) over the sphere's pixels and over the sky's; with
// `variances` (of each pixel's mean) also their standard errors.
inline SkyFurnaceMeans skyFurnaceMeans(int width, int height, const std::vector<float>& values,
                                       const std::vector<float>* variances = nullptr) {
  double sum[2] = {}, varianceSum[2] = {}, count[2] = {};
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const SkyRegion region = skyRegionOf(x, y, width, height);
      if (region == SkyRegion::Silhouette) continue;
      const int r = region == SkyRegion::Sphere ? 0 : 1;
      const size_t p = static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x);
      sum[r] += values[p];
      if (variances) varianceSum[r] += (*variances)[p];
      ++count[r];
    }
  const auto estimate = [&](int r) {
    return MeanEstimate{sum[r] / count[r], std::sqrt(varianceSum[r]) / count[r]};
  };
  return {estimate(0), estimate(1)};
}

// The same for a frame's G channel (the furnace is grey), with variance.G if it has one.
inline SkyFurnaceMeans skyFurnaceMeans(const FrameImage& image) {
  const bool hasVariance = image.hasChannel("variance.G");
  return skyFurnaceMeans(image.width(), image.height(), image.channel("G"),
                         hasVariance ? &image.channel("variance.G") : nullptr);
}

}  // namespace pathfarm::test_support
