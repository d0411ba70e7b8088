#pragma once
// The luminance of linear R, G, B with the Rec. 709 primaries (ITU-R BT.709):
// Y = 0.2126 R + 0.7152 G + 0.0722 B. The renderer's own is Rgb::luminance
// (renderer/math/vecmath.h).
namespace pathfarm {

// The weights of R, G and B, in the precision of T: in double they are the decimal weights
// rounded to double, not the float weights widened.
template <class T>
inline constexpr T kLuminanceWeights[3] = {T(0.2126), T(0.7152), T(0.0722)};

template <class T>
constexpr T luminance(T r, T g, T b) {
  return kLuminanceWeights<T>[0] * r + kLuminanceWeights<T>[1] * g + kLuminanceWeights<T>[2] * b;
}

}  // namespace pathfarm
