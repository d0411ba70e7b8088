#pragma once
// The environment: radiance arriving from infinitely far away, by direction. Either a
// constant, or an equirectangular (latitude-longitude) map times a strength, turned about
// +y. Black (the default) means the scene has no environment.
//
// Map orientation, the convention of three.js's equirectUv(), and of Blender's
// environment texture once Blender's +z-up world is turned +y-up as its glTF exporter
// does (-y becoming +z): with map coordinates (u, v), u across the image from its left
// edge and v down from its top row, a map-space direction d = (x, y, z) is at
//   u = 1/2 + atan2(z, x) / (2 pi),   v = acos(y) / pi.
// The top row is +y, the bottom row -y; the image's centre faces +x, its left and right
// edges -x, u = 3/4 faces +z and u = 1/4 faces -z. Seen from inside, turning right (from
// +x towards +z when +y is up) moves right across the image, so it does not read mirrored.
// `rotation` turns the map by that many degrees about +y (right-handed): the centre then
// faces (cos r, 0, -sin r), -z for 90 degrees.
//
// Sampling as pbrt-v3's InfiniteAreaLight (Pharr, Jakob and Humphreys 2016, Section
// 14.2.4): a piecewise-constant density over the map, proportional to each texel's mean
// radiance luminance times sin(theta), mapped to solid angle by the Jacobian
// 2 pi^2 sin(theta). The constant environment samples the sphere uniformly, as it always
// has, so scenes with a constant sky render the same bits as before maps existed.
#include <memory>
#include <optional>
#include <vector>

#include "renderer/math/vecmath.h"
#include "renderer/sampling/piecewise_constant.h"

namespace pathfarm {

struct EnvironmentSample {
  Vec3f direction;  // unit, towards the environment
  Rgb radiance;     // arriving along -direction
  float pdf;        // solid angle
};

class EnvironmentLight {
 public:
  EnvironmentLight() = default;
  explicit EnvironmentLight(Rgb radiance) : constant_(radiance) {}
  // A map of `width` x `height` texels, row-major, the top row first. Throws
  // std::invalid_argument for a texel that is negative or not finite.
  EnvironmentLight(int width, int height, std::vector<Rgb> texels, float strength, float rotationDegrees);

  bool isBlack() const { return map_ ? map_->black : constant_.isBlack(); }
  // Radiance arriving from `direction` (unit, pointing away from the scene): bilinear
  // between texel centres, wrapping around in u and clamped at the poles.
  Rgb radiance(Vec3f direction) const;
  // A direction with density pdf(direction), up to rounding; nothing where the density is 0.
  std::optional<EnvironmentSample> sample(Vec2f u) const;
  float pdf(Vec3f direction) const;
  // The luminance of the radiance averaged over all directions, for choosing among lights
  // by power.
  float meanLuminance() const { return map_ ? map_->meanLuminance : constant_.luminance(); }

 private:
  struct Map {
    int width = 0, height = 0;
    std::vector<Rgb> texels;  // times the strength
    PiecewiseConstant2D distribution;
    float meanLuminance = 0;
    bool black = true;
  };
  Vec3f toMap(Vec3f world) const;
  Vec3f toWorld(Vec3f map) const;
  Rgb texel(int x, int y) const;

  Rgb constant_;
  std::shared_ptr<const Map> map_;  // shared: scenes are copied
  float cosRotation_ = 1, sinRotation_ = 0;
};

}  // namespace pathfarm
