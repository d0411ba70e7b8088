#pragma once
// Gradient-domain path tracing (Kettunen et al. 2015): every base path is shifted to the
// four neighbouring pixels (shift_mapping.h), and each of its contributions (emitters hit
// by BSDF sampling, next-event estimates) is weighted by one power-heuristic MIS weight
// over the four strategies {light, BSDF} x {base, offset}, the public implementation's
// choice, applied alike to the base's part of the pixel, the offset's part of the
// neighbour and their difference. Emitters seen directly from the camera go to a buffer
// of their own: they take no part in the differences.
#include <array>
#include <optional>

#include "renderer/integrators/path_tracer.h"

namespace pathfarm {

// Shift directions in pixels: +x, -x, +y, -y. Direction k's opposite is k ^ 1.
inline constexpr std::array<std::array<int, 2>, 4> kShiftDirections{{{1, 0}, {-1, 0}, {0, 1}, {0, -1}}};

struct GradientSample {
  Rgb direct;    // emission seen directly from the camera
  Rgb radiance;  // the plain path-traced estimate (path_tracer.h's weights), without direct
  // Per shift direction k, each already weighted by MIS: the base's part of its own pixel,
  // the offset's part of the neighbour, and offset - base.
  std::array<Rgb, 4> base, offset, difference;
};

class GradientPathTracer {
 public:
  GradientPathTracer(const FrameGeometry& geometry, const LightSampler& lights, PathTracerSettings settings)
      : geometry_(geometry), lights_(lights), settings_(settings) {}

  // Traces the base path along `ray` and an offset path along each given offset ray (the
  // camera ray through the neighbouring pixel with the same film jitter, time and lens).
  // A direction without an offset ray (its neighbour lies outside the image) gets the
  // plain path tracer's weights in `base` and no offset. Draws from `stream` exactly as
  // PathTracer::radiance does.
  GradientSample trace(const Ray& ray, const std::array<std::optional<Ray>, 4>& offsetRays, float time,
                       SampleStream& stream, RayCounts& counts) const;

 private:
  const FrameGeometry& geometry_;
  const LightSampler& lights_;
  PathTracerSettings settings_;
};

}  // namespace pathfarm
