#pragma once
// A keyed animation curve of `width` components per key, as glTF samplers store them:
// LINEAR, STEP or CUBICSPLINE (Hermite, with in- and out-tangents beside each value).
// Before the first key and after the last the curve holds its end value.
#include <cstddef>
#include <vector>

namespace pathfarm {

enum class KeyInterpolation { Linear, Step, CubicSpline };

struct KeyTrack {
  KeyInterpolation interpolation = KeyInterpolation::Linear;
  size_t width = 1;
  std::vector<double> times;  // strictly increasing
  // `width` values per key; CUBICSPLINE: in-tangent, value, out-tangent per key.
  std::vector<float> values;

  // The key segment [times[key], times[key + 1]) holding `seconds` and its fraction of
  // it; `hold` outside the keys (then `key` is the end key).
  struct Segment {
    size_t key = 0;
    double fraction = 0;
    bool hold = true;
  };
  Segment locate(double seconds) const;
  // The curve's `width` components at `seconds`, each interpolated on its own (a
  // rotation's components are not slerped here).
  void sample(double seconds, double* out) const;
  // The stored value of key `key`, component `i` (the value, not a tangent).
  float keyValue(size_t key, size_t i) const;
};

}  // namespace pathfarm
