#include "renderer/math/key_track.h"

#include <algorithm>

namespace pathfarm {

KeyTrack::Segment KeyTrack::locate(double seconds) const {
  if (seconds <= times.front()) return {0, 0, true};
  if (seconds >= times.back()) return {times.size() - 1, 0, true};
  const size_t next = static_cast<size_t>(std::upper_bound(times.begin(), times.end(), seconds) - times.begin());
  const size_t key = next - 1;
  return {key, (seconds - times[key]) / (times[next] - times[key]), false};
}

float KeyTrack::keyValue(size_t key, size_t i) const {
  const bool cubic = interpolation == KeyInterpolation::CubicSpline;
  return values[key * (cubic ? 3 : 1) * width + (cubic ? width : 0) + i];
}

void KeyTrack::sample(double seconds, double* out) const {
  const Segment s = locate(seconds);
  if (s.hold || interpolation == KeyInterpolation::Step) {
    for (size_t i = 0; i < width; ++i) out[i] = keyValue(s.key, i);
    return;
  }
  if (interpolation == KeyInterpolation::Linear) {
    for (size_t i = 0; i < width; ++i) {
      const double a = keyValue(s.key, i), b = keyValue(s.key + 1, i);
      out[i] = a + (b - a) * s.fraction;
    }
    return;
  }
  // Cubic Hermite spline (glTF 2.0 specification, appendix C), tangents scaled by the
  // key interval.
  const double t = s.fraction, t2 = t * t, t3 = t2 * t;
  const double span = times[s.key + 1] - times[s.key];
  const auto stored = [&](size_t key, size_t part, size_t i) -> double { return values[(3 * key + part) * width + i]; };
  for (size_t i = 0; i < width; ++i) {
    const double p0 = stored(s.key, 1, i), m0 = stored(s.key, 2, i) * span;
    const double p1 = stored(s.key + 1, 1, i), m1 = stored(s.key + 1, 0, i) * span;
    out[i] = (2 * t3 - 3 * t2 + 1) * p0 + (t3 - 2 * t2 + t) * m0 + (-2 * t3 + 3 * t2) * p1 + (t3 - t2) * m1;
  }
}

}  // namespace pathfarm
