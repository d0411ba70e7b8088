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

}  // namespace pathfarm
