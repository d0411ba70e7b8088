#pragma once
// Shared pieces of the material tests: a deterministic uniform source, quadrature over the
// sphere, and the material configurations the statistical tests run on.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "renderer/materials/bsdf.h"

namespace pathfarm::bsdftest {

// Floats in [0, 1) from a fixed-seed Mersenne twister; 24 bits so 1 is never returned.
class Uniform {
 public:
  explicit Uniform(uint32_t seed) : engine_(seed) {}
  float next() { return static_cast<float>(engine_() >> 8) * 0x1p-24f; }
  Vec2f next2() {
    const float a = next();
    return {a, next()};
  }

 private:
  std::mt19937 engine_;
};

inline Vec3f sphericalDirection(float theta, float phi) {
  const float s = std::sin(theta);
  return {s * std::cos(phi), s * std::sin(phi), std::cos(theta)};
}

// Integral of f(direction) over the solid angle of the cell theta in [t0, t1], phi in
// [p0, p1], dw = sin(theta) dtheta dphi. Adaptive: a 3x3 midpoint estimate is split into
// quadrants until they agree to `tolerance`, because BSDF densities jump where a
// constraint cuts them off (the horizon of the facet normals, total internal reflection)
// and a fixed grid converges only linearly there.
template <typename F>
double integrateCell(const F& f, double t0, double t1, double p0, double p1, double tolerance) {
  const auto midpoint = [&](double a0, double a1, double b0, double b1) {
    double sum = 0;
    for (int i = 0; i < 3; ++i) {
      const double theta = a0 + (i + 0.5) * (a1 - a0) / 3;
      for (int j = 0; j < 3; ++j) {
        sum += f(sphericalDirection(float(theta), float(b0 + (j + 0.5) * (b1 - b0) / 3))) * std::sin(theta);
      }
    }
    return sum * (a1 - a0) * (b1 - b0) / 9;
  };
  const auto refine = [&](const auto& self, double a0, double a1, double b0, double b1, double whole,
                          double tol, int depth) -> double {
    const double am = 0.5 * (a0 + a1), bm = 0.5 * (b0 + b1);
    const double q[4] = {midpoint(a0, am, b0, bm), midpoint(am, a1, b0, bm), midpoint(a0, am, bm, b1),
                         midpoint(am, a1, bm, b1)};
    const double sum = q[0] + q[1] + q[2] + q[3];
    if (depth == 8 || std::abs(sum - whole) <= tol) return sum;
    return self(self, a0, am, b0, bm, q[0], tol / 2, depth + 1) +
           self(self, am, a1, b0, bm, q[1], tol / 2, depth + 1) +
           self(self, a0, am, bm, b1, q[2], tol / 2, depth + 1) +
           self(self, am, a1, bm, b1, q[3], tol / 2, depth + 1);
  };
  return refine(refine, t0, t1, p0, p1, midpoint(t0, t1, p0, p1), tolerance, 0);
}

// Integral over the whole sphere, as a 20 x 40 grid of adaptive cells.
template <typename F>
double integrateSphere(const F& f, double tolerancePerCell = 1e-6) {
  constexpr int kTheta = 20, kPhi = 40;
  double sum = 0;
  for (int i = 0; i < kTheta; ++i) {
    for (int j = 0; j < kPhi; ++j) {
      sum += integrateCell(f, kPi * i / kTheta, kPi * (i + 1) / kTheta, 2 * kPi * j / kPhi,
                           2 * kPi * (j + 1) / kPhi, tolerancePerCell);
    }
  }
  return sum;
}

// |a - b| within relTol of the larger magnitude (and 1e-6 absolute, for zeros).
inline bool nearlyEqual(float a, float b, float relTol) {
  return std::abs(a - b) <= relTol * std::max(std::abs(a), std::abs(b)) + 1e-6f;
}

// A direction uniform over the hemisphere (or sphere), away from the horizon where every
// quantity degenerates.
inline Vec3f randomDirection(Uniform& rng, bool sphere) {
  while (true) {
    const float z = sphere ? 1 - 2 * rng.next() : rng.next();
    if (std::abs(z) < 0.02f) continue;
    const float r = std::sqrt(1 - z * z), phi = 2 * kPi * rng.next();
    return {r * std::cos(phi), r * std::sin(phi), z};
  }
}

constexpr float kRoughnessThreshold = 0.1f;

// A Monte Carlo estimate per channel with its standard error.
struct Estimate {
  Rgb mean, stdError;
};

// The relative index across the interface for a refracted pair seen from wo.
inline float refractionEta(const Material& m, Vec3f wo) { return wo.z > 0 ? m.ior : 1 / m.ior; }

// The sample weight as a flux ratio: transmitted radiance weights carry 1 / eta^2, which
// is a change of units between media, not energy created or lost. The thin-walled
// metallic-roughness transmission stays in the same medium.
inline Rgb fluxWeight(const Material& m, Vec3f wo, const BsdfSample& s) {
  if (wo.z * s.wi.z >= 0 || m.type == MaterialType::MetallicRoughness) return s.weight;
  const float eta = refractionEta(m, wo);
  return s.weight * (eta * eta);
}

// Directional albedo E[weight] from n samples, with its standard error per channel.
inline Estimate directionalAlbedo(const Material& m, Rgb albedo, Vec3f wo, int n, uint32_t seed) {
  const Bsdf bsdf(m, albedo, kRoughnessThreshold);
  Uniform rng(seed);
  double sum[3] = {}, sum2[3] = {};
  for (int i = 0; i < n; ++i) {
    const float uLobe = rng.next();
    const auto s = bsdf.sample(wo, uLobe, rng.next2());
    if (!s) continue;
    const Rgb w = fluxWeight(m, wo, *s);
    for (int c = 0; c < 3; ++c) {
      sum[c] += w[c];
      sum2[c] += double(w[c]) * w[c];
    }
  }
  float mean[3], se[3];
  for (int c = 0; c < 3; ++c) {
    mean[c] = float(sum[c] / n);
    se[c] = float(std::sqrt(std::max(0.0, sum2[c] / n - mean[c] * double(mean[c])) / n));
  }
  return {{mean[0], mean[1], mean[2]}, {se[0], se[1], se[2]}};
}

// Directional albedo of a metallic-roughness sheet (one medium: the weights are flux).
inline Estimate albedo(const Material& m, Rgb base, Vec3f wo, int n = 100000) {
  return directionalAlbedo(m, base, wo, n, 33);
}

inline Vec3f directionFromCos(float cosTheta, float phi = 0.3f) {
  const float s = std::sqrt(std::max(0.0f, 1 - cosTheta * cosTheta));
  return {s * std::cos(phi), s * std::sin(phi), cosTheta};
}

struct MaterialCase {
  std::string name;
  Material material;
  Rgb albedo;
  bool twoSided;  // dielectrics: wo may lie below the surface
};

inline Material makeMaterial(MaterialType type, MicrofacetType distribution, float alpha) {
  Material m;
  m.type = type;
  m.distribution = distribution;
  m.alpha = alpha;
  return m;
}

inline Material metallicRoughness(float roughness, float metallic, float transmission, float ior = 1.5f) {
  Material m;
  m.type = MaterialType::MetallicRoughness;
  m.roughness = roughness;
  m.metallic = metallic;
  m.transmission = transmission;
  m.ior = ior;
  return m;
}

// With KHR_materials_specular's factor and colour.
inline Material withSpecular(Material m, float specular, Rgb color) {
  m.specular = specular;
  m.dielectricSpecularColor = color;
  return m;
}

// Every configuration with a non-delta lobe; colored albedo and default gold-like metal.
// The metallic-roughness sheets are thin-walled: twoSided stays false, since the suites'
// two-sided checks assume refraction (metallic_roughness_test.cpp checks both sides).
inline std::vector<MaterialCase> nonDeltaCases() {
  using MT = MaterialType;
  using MF = MicrofacetType;
  const Rgb albedo{0.8f, 0.5f, 0.2f};
  Material glass133 = makeMaterial(MT::RoughDielectric, MF::GGX, 0.5f);
  glass133.ior = 1.33f;
  return {
      {"Diffuse", makeMaterial(MT::Diffuse, MF::GGX, 0), albedo, false},
      {"RoughConductorGGX", makeMaterial(MT::RoughConductor, MF::GGX, 0.3f), albedo, false},
      {"RoughConductorBeckmann", makeMaterial(MT::RoughConductor, MF::Beckmann, 0.3f), albedo, false},
      {"RoughConductorGGXWide", makeMaterial(MT::RoughConductor, MF::GGX, 0.8f), albedo, false},
      {"RoughDielectricGGX", makeMaterial(MT::RoughDielectric, MF::GGX, 0.3f), albedo, true},
      {"RoughDielectricBeckmann", makeMaterial(MT::RoughDielectric, MF::Beckmann, 0.3f), albedo, true},
      {"RoughDielectricGGXWater", glass133, albedo, true},
      {"RoughPlasticGGX", makeMaterial(MT::RoughPlastic, MF::GGX, 0.2f), albedo, false},
      {"RoughPlasticBeckmann", makeMaterial(MT::RoughPlastic, MF::Beckmann, 0.4f), albedo, false},
      {"PlasticDiffusePart", makeMaterial(MT::Plastic, MF::GGX, 0), albedo, false},
      {"MetallicRoughnessDielectric", metallicRoughness(0.5f, 0, 0), albedo, false},
      {"MetallicRoughnessMetal", metallicRoughness(0.3f, 1, 0), albedo, false},
      {"MetallicRoughnessSharp", metallicRoughness(0.15f, 0.5f, 0.5f), albedo, false},
      {"MetallicRoughnessHalfMetalHalfTransmission", metallicRoughness(0.6f, 0.5f, 0.5f), albedo, false},
      {"MetallicRoughnessTransmission", metallicRoughness(0.4f, 0, 1, 1.33f), albedo, false},
      {"MetallicRoughnessRoughest", metallicRoughness(1, 0.5f, 0.5f, 2.4f), albedo, false},
      {"MetallicRoughnessSmoothDiffusePart", metallicRoughness(0, 0, 0.5f), albedo, false},
      // Blender's Specular 0 (colour 0: no reflection at normal incidence, all at grazing),
      // and a weak tinted coating whose colour passes 1 in one channel.
      {"MetallicRoughnessSpecularColourZero", withSpecular(metallicRoughness(0.5f, 0, 0), 1, Rgb(0)), albedo, false},
      {"MetallicRoughnessSpecularTinted",
       withSpecular(metallicRoughness(0.4f, 0.3f, 0.5f), 0.6f, Rgb(3, 1, 0.2f)), albedo, false},
  };
}

inline std::string caseName(const ::testing::TestParamInfo<MaterialCase>& info) { return info.param.name; }

// Outgoing directions the statistical tests use: near normal, oblique, grazing, and for
// two-sided materials also from inside.
inline std::vector<Vec3f> testDirections(bool twoSided) {
  std::vector<Vec3f> dirs{directionFromCos(0.95f, 0.4f), directionFromCos(0.5f, 2.0f),
                          directionFromCos(0.15f, 4.0f)};
  if (twoSided) {
    dirs.push_back(directionFromCos(-0.7f, 1.0f));
    dirs.push_back(directionFromCos(-0.3f, 5.0f));
  }
  return dirs;
}

// Upper quantile of the chi-square distribution, Wilson and Hilferty 1931: (X/k)^(1/3) is
// close to normal with mean 1 - 2/(9k) and variance 2/(9k).
inline double chiSquareQuantile(int dof, double normalQuantile) {
  const double v = 2.0 / (9.0 * dof);
  const double c = 1 - v + normalQuantile * std::sqrt(v);
  return dof * c * c * c;
}

}  // namespace pathfarm::bsdftest
