#pragma once
// Effective irradiance (Zimmer et al. 2015, Section 5.1): a component's color divided by
// its effective reflectance, so filters work on the smooth illumination rather than on
// textures. Where the reflectance is below the guard the color itself is kept, and
// modulation leaves it as it is: demodulate then modulate gives the color back.
namespace pathfarm {

inline constexpr float kReflectanceGuard = 1e-3f;

inline float effectiveIrradiance(float color, float reflectance) {
  return reflectance < kReflectanceGuard ? color : color / reflectance;
}

inline float modulateIrradiance(float irradiance, float reflectance) {
  return reflectance < kReflectanceGuard ? irradiance : irradiance * reflectance;
}

// A component's light per unit of the pixel it covers: `coverage` is the share of the
// pixel's samples that reached the component's first non-specular vertex. At a silhouette
// the irradiance above carries that share; divided out, the light is as smooth across the
// edge as the illumination itself, and multiplying by a pixel's own share puts it back.
// The share divided out is at least kCoverageFloor: a pixel that a few samples reached
// would otherwise multiply their noise (one sun-lit sample of 64 read as 20 times its
// light, which the filters then spread over its neighbours). Where no sample reached the
// component, or the value is no share at all (NaN, above 1 in a damaged file), nothing is
// divided.
inline constexpr float kCoverageFloor = 0.25f;

inline float coverageShare(float coverage) {
  if (!(coverage > 0.0f && coverage <= 1.0f)) return 1.0f;
  return coverage > kCoverageFloor ? coverage : kCoverageFloor;
}

inline float perCoveredArea(float value, float coverage) { return value / coverageShare(coverage); }

}  // namespace pathfarm
