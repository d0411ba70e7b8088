#pragma once
// Closed forms for a Lambertian floor lit by a point light, seen by a camera looking
// straight at it: the film maps linearly onto a square of the floor, so a frame's mean is
// the mean radiance over that square, found here by the midpoint rule.
#include <cmath>
#include <functional>

namespace pathfarm::test_support {

constexpr double kLitFloorPi = 3.14159265358979323846;

// The mean over the square |x|, |z| <= halfWidth of a radiance L(x, z).
inline double meanOverSquare(double halfWidth, const std::function<double(double, double)>& radiance) {
  const int n = 1000;
  double sum = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      sum += radiance(((i + 0.5) / n * 2 - 1) * halfWidth, ((j + 0.5) / n * 2 - 1) * halfWidth);
  return sum / (static_cast<double>(n) * n);
}

// A light of intensity I at height h above floor point (lx, lz) gives a Lambertian floor
// of albedo a the radiance a / pi * I * falloff * cos / r^2 at (x, z), with cos = h / r.
inline double pointLitRadiance(double albedo, double x, double z, double lx, double h, double lz, double intensity,
                               double falloff = 1) {
  const double dx = x - lx, dz = z - lz;
  const double r = std::sqrt(dx * dx + dz * dz + h * h);
  return albedo / kLitFloorPi * intensity * falloff * h / (r * r * r);
}

}  // namespace pathfarm::test_support
