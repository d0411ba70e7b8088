#include "renderer/lights/environment_light.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "renderer/math/sampling.h"

namespace pathfarm {
namespace {

constexpr double kPiD = 3.14159265358979323846;

int wrap(int i, int n) {
  const int r = i % n;
  return r < 0 ? r + n : r;
}

// Map coordinates (u, v) of a unit map-space direction (environment_light.h).
Vec2f mapCoordinates(Vec3f d) {
  const float u = 0.5f + std::atan2(d.z, d.x) * (0.5f * kInvPi);
  const float v = std::acos(std::clamp(d.y, -1.0f, 1.0f)) * kInvPi;
  return {u, v};
}

// Mean luminance of the bilinear interpolation (wrapping in x, clamped in y) over texel
// (x, y)'s footprint: in each axis the tent between neighbouring centres integrates to
// weights 1/8, 3/4, 1/8 of the texel and its two neighbours. Positive wherever a lookup
// inside the texel can be, so sampling misses no direction with radiance.
std::vector<float> footprintLuminance(int width, int height, const std::vector<Rgb>& texels) {
  constexpr float kWeights[3] = {0.125f, 0.75f, 0.125f};
  std::vector<float> mean(texels.size());
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      float sum = 0;
      for (int dy = -1; dy <= 1; ++dy) {
        const int row = std::clamp(y + dy, 0, height - 1);
        for (int dx = -1; dx <= 1; ++dx) {
          const Rgb& t = texels[static_cast<size_t>(row) * static_cast<size_t>(width) +
                                static_cast<size_t>(wrap(x + dx, width))];
          sum += kWeights[dy + 1] * kWeights[dx + 1] * t.luminance();
        }
      }
      mean[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)] = sum;
    }
  }
  return mean;
}

}  // namespace

EnvironmentLight::EnvironmentLight(int width, int height, std::vector<Rgb> texels, float strength,
                                   float rotationDegrees)
    : cosRotation_(std::cos(rotationDegrees * (kPi / 180))), sinRotation_(std::sin(rotationDegrees * (kPi / 180))) {
  if (width <= 0 || height <= 0 || texels.size() != static_cast<size_t>(width) * static_cast<size_t>(height))
    throw std::invalid_argument(std::to_string(texels.size()) + " texels do not make a " + std::to_string(width) +
                                "x" + std::to_string(height) + " map");
  bool black = true;
  double weightedLuminance = 0;
  for (int y = 0; y < height; ++y) {
    // Solid angle of a texel in row y: (2 pi / width) (cos theta_top - cos theta_bottom).
    const double solidAngle =
        2 * kPiD / width * (std::cos(kPiD * y / height) - std::cos(kPiD * (y + 1) / height));
    for (int x = 0; x < width; ++x) {
      Rgb& t = texels[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)];
      if (!t.isFinite() || t.r < 0 || t.g < 0 || t.b < 0)
        throw std::invalid_argument("texel (" + std::to_string(x) + ", " + std::to_string(y) +
                                    ") is negative or not finite");
      t *= strength;
      black = black && t.isBlack();
      weightedLuminance += solidAngle * t.luminance();
    }
  }
  std::vector<float> weights = footprintLuminance(width, height, texels);
  for (size_t i = 0; i < weights.size(); ++i) {
    const float row = static_cast<float>(i / static_cast<size_t>(width));
    weights[i] *= std::sin(kPi * (row + 0.5f) / static_cast<float>(height));
  }
  PiecewiseConstant2D distribution(weights, width, height);
  const float mean = static_cast<float>(weightedLuminance / (4 * kPiD));
  map_ = std::make_shared<const Map>(Map{width, height, std::move(texels), std::move(distribution), mean, black});
}

Vec3f EnvironmentLight::toMap(Vec3f d) const {
  return {d.x * cosRotation_ - d.z * sinRotation_, d.y, d.x * sinRotation_ + d.z * cosRotation_};
}

Vec3f EnvironmentLight::toWorld(Vec3f d) const {
  return {d.x * cosRotation_ + d.z * sinRotation_, d.y, -d.x * sinRotation_ + d.z * cosRotation_};
}

Rgb EnvironmentLight::texel(int x, int y) const {
  return map_->texels[static_cast<size_t>(y) * static_cast<size_t>(map_->width) + static_cast<size_t>(x)];
}

Rgb EnvironmentLight::radiance(Vec3f direction) const {
  if (!map_) return constant_;
  const Vec2f uv = mapCoordinates(toMap(direction));
  // Texel centres sit at (i + 1/2) / size.
  const float s = uv.x * static_cast<float>(map_->width) - 0.5f;
  const float t = uv.y * static_cast<float>(map_->height) - 0.5f;
  const float sFloor = std::floor(s), tFloor = std::floor(t);
  const float fs = s - sFloor, ft = t - tFloor;
  const int x0 = wrap(static_cast<int>(sFloor), map_->width), x1 = wrap(x0 + 1, map_->width);
  const int y0 = std::clamp(static_cast<int>(tFloor), 0, map_->height - 1);
  const int y1 = std::clamp(static_cast<int>(tFloor) + 1, 0, map_->height - 1);
  const Rgb top = texel(x0, y0) * (1 - fs) + texel(x1, y0) * fs;
  const Rgb bottom = texel(x0, y1) * (1 - fs) + texel(x1, y1) * fs;
  return top * (1 - ft) + bottom * ft;
}

std::optional<EnvironmentSample> EnvironmentLight::sample(Vec2f u) const {
  if (!map_) return EnvironmentSample{sampleUniformSphere(u), constant_, kUniformSpherePdf};
  const PiecewiseConstant2D::Sample s = map_->distribution.sample(u);
  const float theta = kPi * s.point.y, phi = 2 * kPi * (s.point.x - 0.5f);
  const float sinTheta = std::sin(theta);
  // d omega = sin(theta) d theta d phi = 2 pi^2 sin(theta) du dv.
  const float pdf = s.pdf / (2 * kPi * kPi * sinTheta);
  if (!(sinTheta > 0) || !(pdf > 0) || !std::isfinite(pdf)) return std::nullopt;
  const Vec3f direction = toWorld({sinTheta * std::cos(phi), std::cos(theta), sinTheta * std::sin(phi)});
  return EnvironmentSample{direction, radiance(direction), pdf};
}

float EnvironmentLight::pdf(Vec3f direction) const {
  if (!map_) return kUniformSpherePdf;
  const Vec3f d = toMap(direction);
  const float sinTheta = std::sqrt(d.x * d.x + d.z * d.z);
  if (!(sinTheta > 0)) return 0;
  const Vec2f uv = mapCoordinates(d);
  const int x = std::clamp(static_cast<int>(uv.x * static_cast<float>(map_->width)), 0, map_->width - 1);
  const int y = std::clamp(static_cast<int>(uv.y * static_cast<float>(map_->height)), 0, map_->height - 1);
  return map_->distribution.pdf(x, y) / (2 * kPi * kPi * sinTheta);
}

}  // namespace pathfarm
